#pragma once
// A survey photo read whole, safely, by every reader (the refiner, visual
// odometry, stereo-locate, the command line): its header is checked first
// (image_header.h: a regular file, at most max_pixels), then the file is
// read and decoded by OpenCV unchanged (any depth and channels), and
// nothing throws. The build's pipeline decodes JPEGs by rows
// (core/mosaic/frame_image.h) but shares the two steps below.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/image/image_header.h"

namespace seamap {

// The whole guarded read. On failure returns an empty image and sets
// *problem: "missing image", "not a regular file: ...", "image too large:
// ...", "unreadable image: ...".
cv::Mat ReadGuardedImage(const std::string& path, std::string* problem, int64_t max_pixels = kDefaultMaxImagePixels);

// The file's bytes, once its header (read by ReadImageHeader) is known not
// to be too large; nullopt and *problem otherwise.
std::optional<std::vector<unsigned char>> ReadImageBytes(const std::string& path, const ImageHeader& header,
                                                         int64_t max_pixels, std::string* problem);

// OpenCV's decoding of `bytes`, unchanged; an empty image and *problem when
// it refuses them, or when the decoded image (of a format whose header does
// not give its size) has more than max_pixels.
cv::Mat DecodeImageBytes(const std::vector<unsigned char>& bytes, const ImageHeader& header, int64_t max_pixels,
                         std::string* problem);

}  // namespace seamap
