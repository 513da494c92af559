#include "server/photo_preview.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace seamap::server {
namespace {

std::string BrowserType(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  if (ext == ".png") return "image/png";
  if (ext == ".webp") return "image/webp";
  return "";
}

}  // namespace

std::optional<Photo> LoadPhoto(const std::string& path, int max_side) {
  const std::string type = BrowserType(path);
  if (max_side <= 0 && !type.empty()) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    return Photo{std::string(std::istreambuf_iterator<char>(in), {}), type};
  }
  cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) return std::nullopt;
  if (image.depth() != CV_8U) {  // 16-bit or float: stretch to 8 bits for display
    double lo, hi;
    cv::minMaxLoc(image.reshape(1), &lo, &hi);
    image.convertTo(image, CV_8U, hi > lo ? 255.0 / (hi - lo) : 1.0, hi > lo ? -lo * 255.0 / (hi - lo) : 0);
  }
  if (max_side > 0 && std::max(image.cols, image.rows) > max_side) {
    const double s = double(max_side) / std::max(image.cols, image.rows);
    cv::resize(image, image, cv::Size(), s, s, cv::INTER_AREA);
  }
  std::vector<uint8_t> out;
  const bool jpeg = max_side > 0;
  if (!cv::imencode(jpeg ? ".jpg" : ".png", image, out,
                    jpeg ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, 85} : std::vector<int>{}))
    return std::nullopt;
  return Photo{std::string(out.begin(), out.end()), jpeg ? "image/jpeg" : "image/png"};
}

}  // namespace seamap::server
