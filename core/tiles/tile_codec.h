#pragma once
// Tile image encoding. Tiles are 8-bit with alpha in RAM: CV_8UC2 (gray,
// alpha) or CV_8UC4 (BGRA). PNG and WebP keep alpha; JPEG has none, so
// transparent pixels are painted with the declared background colour.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace seamap {

enum class TileFormat { kPng, kJpeg, kWebp };

// "png" | "jpg" | "jpeg" | "webp" -> format; throws InputError(source, 0, "tile_format", ...).
TileFormat ParseTileFormat(const std::string& name, const std::string& source);
std::string TileExtension(TileFormat f);  // "png", "jpg", "webp"
std::string TileMimeType(TileFormat f);   // "image/png", ...

struct TileEncoding {
  TileFormat format = TileFormat::kPng;
  int png_level = 1;               // zlib level 0..9
  int jpeg_quality = 85;           // 1..100
  int webp_quality = 85;           // 1..100 (101 = lossless)
  cv::Scalar background{0, 0, 0};  // BGR used under transparent pixels in JPEG
};

// Gray+alpha PNGs are written as PNG gray-alpha (colour type 4, via libpng),
// BGRA as RGBA. Fully opaque tiles drop alpha (gray / RGB PNG, RGB WebP) to
// save bytes. Gray WebP is written as RGB (WebP has no gray mode).
// Throws std::invalid_argument unless tile is CV_8UC2 or CV_8UC4.
std::vector<uint8_t> EncodeTile(const cv::Mat& tile, const TileEncoding& enc);

// Decodes to CV_8UC2 when the data is gray (with or without alpha): a gray
// or gray+alpha PNG, a gray JPEG, or any image whose B, G and R are equal at
// every pixel; CV_8UC4 otherwise. Images without alpha come back fully
// opaque (alpha 255). Throws std::runtime_error on undecodable data.
cv::Mat DecodeTile(const std::vector<uint8_t>& bytes);

// A decoded tile in the layout a mosaic paints: CV_8UC2 for colour_channels
// 1, CV_8UC4 for 3, converting gray <-> colour and keeping alpha. (A colour
// tile whose pixels are all gray decodes as CV_8UC2.)
cv::Mat WithColourChannels(const cv::Mat& tile, int colour_channels);

}  // namespace seamap
