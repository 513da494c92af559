#include "core/image/image_header.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <vector>

#include "core/util/input_file.h"

namespace seamap {
namespace {

// An open file read at offsets; closes itself.
class File {
 public:
  explicit File(int fd) : fd_(fd) {}
  ~File() {
    if (fd_ >= 0) ::close(fd_);
  }
  File(const File&) = delete;
  File& operator=(const File&) = delete;

  // Up to n bytes at `offset` (fewer at the end of the file).
  std::vector<unsigned char> Read(int64_t offset, size_t n) const {
    std::vector<unsigned char> out(n);
    size_t got = 0;
    while (got < n) {
      const ssize_t r = ::pread(fd_, out.data() + got, n - got, static_cast<off_t>(offset + got));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) break;
      got += static_cast<size_t>(r);
    }
    out.resize(got);
    return out;
  }

 private:
  int fd_;
};

uint32_t Be16(const unsigned char* p) {
  return (uint32_t{p[0]} << 8) | p[1];
}
uint32_t Be32(const unsigned char* p) {
  return (Be16(p) << 16) | Be16(p + 2);
}
uint32_t Le16(const unsigned char* p) {
  return (uint32_t{p[1]} << 8) | p[0];
}
uint32_t Le32(const unsigned char* p) {
  return (Le16(p + 2) << 16) | Le16(p);
}
uint32_t Le24(const unsigned char* p) {
  return (uint32_t{p[2]} << 16) | Le16(p);
}

bool StartsWith(const std::vector<unsigned char>& bytes, const char* magic, size_t n, size_t at = 0) {
  return bytes.size() >= at + n && std::memcmp(bytes.data() + at, magic, n) == 0;
}

std::string Broken(const std::string& format, const std::string& what) {
  return "unreadable image: broken " + format + " header (" + what + ")";
}

// PNG: the IHDR chunk comes first.
bool ReadPng(const std::vector<unsigned char>& b, ImageHeader* h, std::string* problem) {
  if (b.size() < 26 || !StartsWith(b, "IHDR", 4, 12)) return *problem = Broken("PNG", "no IHDR chunk"), false;
  h->width = Be32(&b[16]);
  h->height = Be32(&b[20]);
  switch (b[25]) {  // colour type
    case 0:
      h->channels = 1;
      break;
    case 4:
      h->channels = 2;
      break;
    case 2:
    case 3:
      h->channels = 3;
      break;
    case 6:
      h->channels = 4;
      break;
    default:
      return *problem = Broken("PNG", "colour type " + std::to_string(b[25])), false;
  }
  return true;
}

// JPEG: walk the marker segments (EXIF blocks may come first) to the frame header.
bool ReadJpeg(const File& file, int64_t size, ImageHeader* h, std::string* problem) {
  int64_t at = 2;
  for (int segments = 0; segments < 10000 && at + 4 <= size; ++segments) {
    const std::vector<unsigned char> m = file.Read(at, 4);
    if (m.size() < 4 || m[0] != 0xFF) return *problem = Broken("JPEG", "no marker where one belongs"), false;
    const unsigned marker = m[1];
    if (marker == 0xFF) {  // fill byte
      ++at;
      continue;
    }
    if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) {  // no length
      at += 2;
      continue;
    }
    if (marker == 0xDA || marker == 0xD9) break;  // scan data or the end before a frame header
    const uint32_t length = Be16(&m[2]);
    if (length < 2) return *problem = Broken("JPEG", "segment length below 2"), false;
    const bool frame_header = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame_header) {
      const std::vector<unsigned char> f = file.Read(at + 4, 6);
      if (f.size() < 6) break;
      h->height = Be16(&f[1]);
      h->width = Be16(&f[3]);
      h->channels = f[5] == 1 ? 1 : 3;  // OpenCV reads CMYK and YCCK as BGR too
      if (h->width == 0 || h->height == 0)
        return *problem = Broken("JPEG", "frame of " + std::to_string(h->width) + "x" + std::to_string(h->height)),
               false;
      return true;
    }
    at += 2 + length;
  }
  *problem = Broken("JPEG", "no frame header");
  return false;
}

// TIFF: the first image directory's width, length and samples per pixel.
bool ReadTiff(const File& file, const std::vector<unsigned char>& b, ImageHeader* h, std::string* problem) {
  const bool le = b[0] == 'I';
  auto u16 = [le](const unsigned char* p) { return le ? Le16(p) : Be16(p); };
  auto u32 = [le](const unsigned char* p) { return le ? Le32(p) : Be32(p); };
  if (u16(&b[2]) != 42) {  // BigTIFF (43) and others: OpenCV decides
    h->format.clear();
    return true;
  }
  const uint32_t ifd = u32(&b[4]);
  const std::vector<unsigned char> count_bytes = file.Read(ifd, 2);
  if (count_bytes.size() < 2) return *problem = Broken("TIFF", "image directory past the end of the file"), false;
  const uint32_t count = u16(count_bytes.data());
  const std::vector<unsigned char> entries = file.Read(int64_t{ifd} + 2, size_t{count} * 12);
  int samples = 1;
  for (size_t i = 0; i + 12 <= entries.size(); i += 12) {
    const unsigned char* e = &entries[i];
    const uint32_t tag = u16(e), type = u16(e + 2);
    const uint32_t value = type == 3 ? u16(e + 8) : u32(e + 8);  // SHORT or LONG, held in the entry
    if (tag == 256) h->width = value;
    if (tag == 257) h->height = value;
    if (tag == 277) samples = static_cast<int>(value);
  }
  if (h->width == 0 || h->height == 0) return *problem = Broken("TIFF", "no image width or length"), false;
  h->channels = samples >= 1 && samples <= 4 ? samples : 0;
  return true;
}

bool ReadBmp(const std::vector<unsigned char>& b, ImageHeader* h, std::string* problem) {
  if (b.size() < 26) return *problem = Broken("BMP", "too short"), false;
  const uint32_t dib = Le32(&b[14]);
  int bits = 0;
  if (dib == 12) {  // OS/2
    h->width = Le16(&b[18]);
    h->height = Le16(&b[20]);
    bits = b.size() >= 26 ? static_cast<int>(Le16(&b[24])) : 0;
  } else if (dib >= 40 && b.size() >= 30) {
    h->width = static_cast<int32_t>(Le32(&b[18]));
    h->height = static_cast<int32_t>(Le32(&b[22]));
    if (h->height < 0) h->height = -h->height;  // top-down rows
    bits = static_cast<int>(Le16(&b[28]));
  } else {
    return *problem = Broken("BMP", "unknown header size " + std::to_string(dib)), false;
  }
  if (h->width <= 0 || h->height <= 0) return *problem = Broken("BMP", "no width or height"), false;
  h->channels = bits == 32 ? 4 : bits > 8 ? 3 : 0;  // palettes: gray or colour, OpenCV decides
  return true;
}

bool ReadWebp(const std::vector<unsigned char>& b, ImageHeader* h, std::string* problem) {
  if (b.size() < 30) return *problem = Broken("WebP", "too short"), false;
  if (StartsWith(b, "VP8X", 4, 12)) {
    h->width = Le24(&b[24]) + 1;
    h->height = Le24(&b[27]) + 1;
    h->channels = (b[20] & 0x10) ? 4 : 3;
  } else if (StartsWith(b, "VP8L", 4, 12)) {
    const uint32_t bits = Le32(&b[21]);
    h->width = (bits & 0x3FFF) + 1;
    h->height = ((bits >> 14) & 0x3FFF) + 1;
    h->channels = (bits >> 28) & 1 ? 4 : 3;
  } else if (StartsWith(b, "VP8 ", 4, 12)) {
    h->width = Le16(&b[26]) & 0x3FFF;
    h->height = Le16(&b[28]) & 0x3FFF;
    h->channels = 3;
  } else {
    return *problem = Broken("WebP", "no VP8 chunk"), false;
  }
  return true;
}

}  // namespace

std::optional<ImageHeader> ReadImageHeader(const std::string& path, std::string* problem) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    *problem = error == ENOENT || error == ENOTDIR ? "missing image"
                                                   : std::string("unreadable image: ") + std::strerror(error);
    return std::nullopt;
  }
  File file(fd);
  struct stat st {};
  if (::fstat(fd, &st) != 0) {
    *problem = std::string("unreadable image: ") + std::strerror(errno);
    return std::nullopt;
  }
  if (!S_ISREG(st.st_mode)) {
    *problem = std::string("not a regular file: ") + FileKindOf(st.st_mode) + ", skipped unread";
    return std::nullopt;
  }
  ImageHeader h;
  h.file_bytes = st.st_size;
  const std::vector<unsigned char> b = file.Read(0, 64);
  bool ok = true;
  if (StartsWith(b, "\x89PNG\r\n\x1a\n", 8)) {
    h.format = "png";
    ok = ReadPng(b, &h, problem);
  } else if (b.size() >= 3 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF) {
    h.format = "jpeg";
    ok = ReadJpeg(file, h.file_bytes, &h, problem);
  } else if (b.size() >= 8 && (StartsWith(b, "II", 2) || StartsWith(b, "MM", 2))) {
    h.format = "tiff";
    ok = ReadTiff(file, b, &h, problem);
  } else if (StartsWith(b, "BM", 2)) {
    h.format = "bmp";
    ok = ReadBmp(b, &h, problem);
  } else if (StartsWith(b, "RIFF", 4) && StartsWith(b, "WEBP", 4, 8)) {
    h.format = "webp";
    ok = ReadWebp(b, &h, problem);
  }
  if (!ok) return std::nullopt;
  return h;
}

std::optional<std::string> TooLargeToDecode(const ImageHeader& header, int64_t max_pixels) {
  if (header.pixels() > max_pixels)
    return "image too large: its header says " + std::to_string(header.width) + "x" + std::to_string(header.height) +
           " pixels, over the limit of " + std::to_string(max_pixels) + " (max_image_pixels); not decoded";
  // 16-bit RGBA with no compression at all is 8 bytes a pixel; a file much
  // larger than that (or than the limit, for formats read by OpenCV) is not
  // an image of that size.
  const int64_t pixels = header.width > 0 ? header.pixels() : max_pixels;
  const int64_t most_bytes = pixels * 8 + (int64_t{16} << 20);
  if (header.file_bytes > most_bytes)
    return "image too large: the file has " + std::to_string(header.file_bytes) + " bytes, more than " +
           std::to_string(most_bytes) + " for " + std::to_string(pixels) + " pixels; not read";
  return std::nullopt;
}

}  // namespace seamap
