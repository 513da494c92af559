#include "core/enhance/pixel_format.h"

#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {

void RequireSupportedImage(const cv::Mat& image, const std::string& op) {
  if (image.empty()) throw InputError("", 0, op, "expected an image, got an empty one");
  int t = image.type();
  if (t == CV_8UC1 || t == CV_8UC3 || t == CV_16UC1 || t == CV_16UC3) return;
  throw InputError(
      "", 0, op,
      "expected an 8- or 16-bit gray or BGR image (CV_8UC1, CV_8UC3, CV_16UC1, CV_16UC3), got " + cv::typeToString(t));
}

double FullScale(const cv::Mat& image) {
  return image.depth() == CV_16U ? 65535.0 : 255.0;
}

cv::Mat ToUnitFloat(const cv::Mat& image) {
  cv::Mat out;
  image.convertTo(out, CV_32F, 1.0 / FullScale(image));
  return out;
}

cv::Mat FromUnitFloat(const cv::Mat& unit, int type) {
  cv::Mat out;
  unit.convertTo(out, CV_MAT_DEPTH(type), CV_MAT_DEPTH(type) == CV_16U ? 65535.0 : 255.0);
  return out;
}

cv::Mat ToGray8(const cv::Mat& image) {
  cv::Mat gray = image;
  if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  if (image.channels() == 4) cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  if (gray.depth() == CV_8U) return gray;
  cv::Mat out;
  gray.convertTo(out, CV_8U, 255.0 / FullScale(gray));
  return out;
}

cv::Mat UnitLuminance(const cv::Mat& unit) {
  if (unit.channels() == 1) return unit;
  cv::Mat gray;
  cv::cvtColor(unit, gray, cv::COLOR_BGR2GRAY);
  return gray;
}

}  // namespace seamap
