#pragma once
// Pixel formats the enhancement operations accept (8/16-bit gray or BGR) and
// conversions to and from a unit-range float working copy.
#include <string>

#include <opencv2/core.hpp>

namespace seamap {

// Throws InputError(field = op) unless image is CV_8UC1, CV_8UC3, CV_16UC1 or CV_16UC3.
void RequireSupportedImage(const cv::Mat& image, const std::string& op);

// 255 for 8-bit, 65535 for 16-bit images.
double FullScale(const cv::Mat& image);

// CV_32FC(n) copy scaled to [0, 1].
cv::Mat ToUnitFloat(const cv::Mat& image);

// Back to `type` (one of the supported types, same channel count), saturating.
cv::Mat FromUnitFloat(const cv::Mat& unit, int type);

// 8-bit single-channel view of any supported image, BGRA too (for detectors and metrics).
cv::Mat ToGray8(const cv::Mat& image);

// Single-channel luminance of a unit float image (itself when already gray).
cv::Mat UnitLuminance(const cv::Mat& unit);

}  // namespace seamap
