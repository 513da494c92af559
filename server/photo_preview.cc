#include "server/photo_preview.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/image/image_header.h"
#include "core/image/image_read.h"

namespace seamap::server {
namespace {

namespace fs = std::filesystem;

std::string BrowserType(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  if (ext == ".png") return "image/png";
  if (ext == ".webp") return "image/webp";
  return "";
}

// What the bytes are, by their signature: "" for anything else.
std::string SniffedType(const std::string& b) {
  if (b.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0) return "image/png";
  if (b.size() >= 3 && static_cast<unsigned char>(b[0]) == 0xff && static_cast<unsigned char>(b[1]) == 0xd8 &&
      static_cast<unsigned char>(b[2]) == 0xff)
    return "image/jpeg";
  if (b.size() >= 12 && b.compare(0, 4, "RIFF") == 0 && b.compare(8, 4, "WEBP") == 0) return "image/webp";
  return "";
}

// The path with symlinks and dot segments resolved; empty when it does not exist.
fs::path Resolved(const fs::path& path) {
  std::error_code ec;
  fs::path out = fs::canonical(path, ec);
  return ec ? fs::path() : out;
}

bool Inside(const fs::path& file, const fs::path& folder) {
  if (file.empty() || folder.empty()) return false;
  const std::string f = file.string(), d = folder.string();
  if (d == "/") return true;
  return f.size() > d.size() && f.compare(0, d.size(), d) == 0 && f[d.size()] == '/';
}

// A file name from the navigation that stays below the folder it is joined to.
bool IsPlainRelative(const fs::path& name) {
  if (name.empty() || name.is_absolute()) return false;
  for (const fs::path& part : name)
    if (part == "..") return false;
  return true;
}

// The file's bytes: a regular file (opened without blocking: a FIFO is refused,
// not waited on), at most kMaxPhotoBytes, read within kPhotoReadTimeout.
std::optional<std::string> ReadRegularFile(const std::string& path, std::string* problem) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    *problem = std::string("cannot open: ") + std::strerror(errno);
    return std::nullopt;
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    *problem = "not a regular file";
    return std::nullopt;
  }
  if (st.st_size > kMaxPhotoBytes) {
    *problem = "larger than " + std::to_string(kMaxPhotoBytes >> 20) + " MB";
    return std::nullopt;
  }
  const auto deadline = std::chrono::steady_clock::now() + kPhotoReadTimeout;
  std::string bytes(static_cast<size_t>(st.st_size), '\0');
  size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t r = ::read(fd, &bytes[got], std::min<size_t>(bytes.size() - got, 1 << 20));
    if (r < 0 && (errno == EINTR || errno == EAGAIN)) {
      if (std::chrono::steady_clock::now() > deadline) break;
      continue;
    }
    if (r <= 0) break;  // shrank meanwhile: what there is
    got += static_cast<size_t>(r);
    if (std::chrono::steady_clock::now() > deadline) {
      *problem = "not read within " + std::to_string(kPhotoReadTimeout.count()) + " s";
      return std::nullopt;
    }
  }
  bytes.resize(got);
  return bytes;
}

}  // namespace

std::string PhotoFolderOf(const FrameRecord& frame) {
  const fs::path recorded(frame.image_path), name(frame.image);
  if (recorded.empty()) return "";
  // The recorded path is the build's --images joined with the navigation's name.
  std::vector<fs::path> tail(name.begin(), name.end());
  std::vector<fs::path> parts(recorded.begin(), recorded.end());
  if (IsPlainRelative(name) && !tail.empty() && parts.size() > tail.size() &&
      std::equal(tail.rbegin(), tail.rend(), parts.rbegin())) {
    fs::path folder;
    for (size_t i = 0; i + tail.size() < parts.size(); ++i) folder /= parts[i];
    return folder.string();
  }
  const fs::path parent = recorded.parent_path();
  return parent.empty() ? "." : parent.string();
}

std::optional<std::string> ResolvePhoto(const FrameRecord& frame, const PhotoFolders& folders, std::string* problem) {
  const fs::path mission_folder = folders.mission_folder.empty() ? fs::path() : Resolved(folders.mission_folder);
  const fs::path photo_dir = folders.photo_dir.empty() ? fs::path() : Resolved(folders.photo_dir);
  if (!frame.image_path.empty()) {
    const fs::path recorded = Resolved(frame.image_path);
    if (Inside(recorded, mission_folder) || Inside(recorded, photo_dir)) return recorded.string();
  }
  if (!photo_dir.empty() && IsPlainRelative(frame.image)) {
    const fs::path by_name = Resolved(photo_dir / frame.image);
    if (Inside(by_name, photo_dir)) return by_name.string();
  }
  *problem = "not in the mission's photo folder" +
             (folders.mission_folder.empty() ? std::string() : " (" + folders.mission_folder + ")") +
             (folders.photo_dir.empty() ? std::string(" and no --images given") : " nor in --images") + ", or missing";
  return std::nullopt;
}

std::optional<Photo> LoadPhoto(const std::string& path, int max_side, std::string* problem) {
  std::optional<std::string> bytes = ReadRegularFile(path, problem);
  if (!bytes) return std::nullopt;
  const std::string type = BrowserType(path), sniffed = SniffedType(*bytes);
  if (!type.empty() && sniffed != type) {
    *problem = "its bytes are not the " + type + " its name says";
    return std::nullopt;
  }
  if (max_side <= 0 && !type.empty()) return Photo{std::move(*bytes), type};
  // Decoded: the header first, so a small file claiming a huge image is refused unread.
  const std::optional<ImageHeader> header = ReadImageHeader(path, problem);
  if (!header) return std::nullopt;
  if (auto too_large = TooLargeToDecode(*header, kDefaultMaxImagePixels)) {
    *problem = *too_large;
    return std::nullopt;
  }
  cv::Mat image = DecodeImageBytes(std::vector<unsigned char>(bytes->begin(), bytes->end()), *header,
                                   kDefaultMaxImagePixels, problem);
  bytes.reset();
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
                    jpeg ? std::vector<int>{cv::IMWRITE_JPEG_QUALITY, 85} : std::vector<int>{})) {
    *problem = "cannot be encoded for the browser";
    return std::nullopt;
  }
  return Photo{std::string(out.begin(), out.end()), jpeg ? "image/jpeg" : "image/png"};
}

bool PhotoGate::Enter(std::chrono::milliseconds wait) {
  std::unique_lock<std::mutex> lock(mutex_);
  if (!freed_.wait_for(lock, wait, [this] { return free_ > 0; })) return false;
  --free_;
  return true;
}

void PhotoGate::Leave() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++free_;
  }
  freed_.notify_one();
}

}  // namespace seamap::server
