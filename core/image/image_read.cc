#include "core/image/image_read.h"

#include <algorithm>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

namespace seamap {

cv::Mat ReadGuardedImage(const std::string& path, std::string* problem, int64_t max_pixels) {
  const std::optional<ImageHeader> header = ReadImageHeader(path, problem);
  if (!header) return cv::Mat();
  const auto bytes = ReadImageBytes(path, *header, max_pixels, problem);
  if (!bytes) return cv::Mat();
  return DecodeImageBytes(*bytes, *header, max_pixels, problem);
}

std::optional<std::vector<unsigned char>> ReadImageBytes(const std::string& path, const ImageHeader& header,
                                                         int64_t max_pixels, std::string* problem) {
  if (auto too_large = TooLargeToDecode(header, max_pixels)) {
    *problem = *too_large;
    return std::nullopt;
  }
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) {
    *problem = "missing image";
    return std::nullopt;
  }
  std::vector<unsigned char> bytes(static_cast<size_t>(std::max<std::streamoff>(0, in.tellg())));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()))) {
    *problem = "unreadable image: cannot read the file";
    return std::nullopt;
  }
  return bytes;
}

cv::Mat DecodeImageBytes(const std::vector<unsigned char>& bytes, const ImageHeader& header, int64_t max_pixels,
                         std::string* problem) {
  cv::Mat raw;
  try {  // OpenCV throws on what its decoders refuse (e.g. its own size limit)
    if (!bytes.empty()) raw = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    *problem = "unreadable image: " + e.msg;
    return cv::Mat();
  }
  if (raw.empty()) {
    *problem = "unreadable image";
    return cv::Mat();
  }
  // Formats whose header we do not read are checked once decoded.
  if (int64_t{raw.cols} * raw.rows > max_pixels) {
    ImageHeader decoded = header;
    decoded.width = raw.cols;
    decoded.height = raw.rows;
    *problem = *TooLargeToDecode(decoded, max_pixels);
    return cv::Mat();
  }
  return raw;
}

}  // namespace seamap
