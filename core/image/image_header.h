#pragma once
// What an image file says about itself before a pixel is decoded: its size
// and channels, read from the header of the formats surveys use (PNG, JPEG,
// TIFF, BMP, WebP) without reading the image data. A header can claim any
// size (a 875 KB PNG holds 30000 x 30000 zeros), so the size is checked
// before decoding. The file is opened without blocking and must be a
// regular file: a FIFO among the photos would wait for a writer for ever.
#include <cstdint>
#include <optional>
#include <string>

namespace seamap {

// Frames larger than this (pixels) are refused unread by default.
constexpr int64_t kDefaultMaxImagePixels = 100'000'000;

struct ImageHeader {
  std::string format;             // "png", "jpeg", "tiff", "bmp", "webp"; empty: another format (OpenCV decodes it)
  int64_t width = 0, height = 0;  // 0 when the format is not one of those above
  int channels = 0;               // as OpenCV reads it unchanged (1, 2, 3, 4); 0: unknown
  int64_t file_bytes = 0;
  int64_t pixels() const { return width * height; }
};

// Reads the header of `path`. On failure returns nullopt and sets *problem:
// "missing image", "not a regular file: a FIFO" (or a folder, a device, a
// socket), "unreadable image: ..." (a broken header of a known format).
std::optional<ImageHeader> ReadImageHeader(const std::string& path, std::string* problem);

// Why a frame with this header is refused before decoding, or nullopt:
// over `max_pixels` ("image too large: ..."), or a file larger than any
// image of that many pixels could be.
std::optional<std::string> TooLargeToDecode(const ImageHeader& header, int64_t max_pixels);

}  // namespace seamap
