#pragma once
// A survey photo on its way to the map, as 8-bit gray or BGR. A JPEG stays
// compressed until the warp knows which rows it samples: libjpeg-turbo then
// decodes only those (rows above are skipped without the inverse DCT, rows
// below are never read). A frame that hands most of itself over to its
// neighbours samples a band of rows, so this saves most of the decoding.
// Other formats (and JPEGs libjpeg cannot decode by rows) are decoded in
// full by OpenCV when read.
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/image/image_read.h"

namespace seamap {

class FrameImage {
 public:
  FrameImage() = default;
  // Reads and checks `path`. On failure returns nullopt and sets *problem
  // ("missing image", "not a regular file: ...", "image too large: ...",
  // "unreadable image: ...", "truncated JPEG ..."). The header is checked
  // (core/image/image_read.h) before the file is read: images of more than
  // max_pixels are refused unread.
  static std::optional<FrameImage> Read(const std::string& path, int channels, int sixteen_bit_white,
                                        std::string* problem, int64_t max_pixels = kDefaultMaxImagePixels);
  // The same with the header already read (ReadImageHeader): a caller that
  // checked it first does not read it twice.
  static std::optional<FrameImage> Read(const std::string& path, const ImageHeader& header, int channels,
                                        int sixteen_bit_white, std::string* problem,
                                        int64_t max_pixels = kDefaultMaxImagePixels);
  // An image already decoded (any depth/channels OpenCV reads; converted).
  static FrameImage FromMat(const cv::Mat& image, int channels, int sixteen_bit_white);

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return width_ == 0; }

  // The frame with at least rows [first, last] decoded; other rows hold
  // anything. Throws InputError naming the file if the JPEG data is broken.
  // Not thread-safe: one job at a time.
  const cv::Mat& Rows(int first, int last);
  const cv::Mat& Full() { return Rows(0, height_ - 1); }
  // Releases the pixels and the compressed data.
  void Release();

 private:
  void DecodeJpegRows(int first, int last);

  std::string path_;
  std::vector<unsigned char> jpeg_;  // compressed frame, when decoding by rows
  int channels_ = 1;
  int width_ = 0, height_ = 0;
  cv::Mat pixels_;
  int decoded_first_ = 0, decoded_last_ = -1;
};

// Converts any image OpenCV reads (gray/colour/alpha, 8/16 bit) to 8-bit with
// `channels` channels. 16-bit values are scaled by 255/white.
cv::Mat ToEightBit(const cv::Mat& image, int channels, int sixteen_bit_white);

}  // namespace seamap
