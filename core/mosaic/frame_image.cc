#include "core/mosaic/frame_image.h"

#include <algorithm>
#include <csetjmp>
#include <cstdio>
#include <stdexcept>

#include <jpeglib.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

bool IsJpeg(const std::vector<unsigned char>& bytes) {
  return bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
}

// A JPEG that stops before its end-of-image marker decodes with grey garbage
// at the bottom (libjpeg only warns), so look for the marker ourselves (it
// may be followed by padding bytes).
bool LooksTruncated(const std::vector<unsigned char>& bytes) {
  const size_t tail = std::min<size_t>(bytes.size(), 64);
  for (size_t i = bytes.size() - tail; i + 1 < bytes.size(); ++i)
    if (bytes[i] == 0xFF && bytes[i + 1] == 0xD9) return false;
  return true;
}

// libjpeg reports fatal errors through error_exit, which must not return:
// jump back to the caller with the message.
struct JpegErrors {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void OnJpegError(j_common_ptr cinfo) {
  auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
  cinfo->err->format_message(cinfo, errors->message);
  std::longjmp(errors->jump, 1);
}

void IgnoreJpegMessage(j_common_ptr, int) {}  // warnings: OpenCV ignores them too

// The decompressor set up on `bytes` with the header read.
class JpegReader {
 public:
  explicit JpegReader(const std::vector<unsigned char>& bytes) {
    cinfo_.err = jpeg_std_error(&errors_.mgr);
    errors_.mgr.error_exit = OnJpegError;
    errors_.mgr.emit_message = IgnoreJpegMessage;
    jpeg_create_decompress(&cinfo_);
    jpeg_mem_src(&cinfo_, bytes.data(), static_cast<unsigned long>(bytes.size()));
  }
  ~JpegReader() { jpeg_destroy_decompress(&cinfo_); }
  JpegReader(const JpegReader&) = delete;
  JpegReader& operator=(const JpegReader&) = delete;

  jpeg_decompress_struct cinfo_{};
  JpegErrors errors_{};
};

}  // namespace

cv::Mat ToEightBit(const cv::Mat& image, int channels, int sixteen_bit_white) {
  cv::Mat eight;
  if (image.depth() == CV_8U)
    eight = image;
  else if (image.depth() == CV_16U)
    image.convertTo(eight, CV_8U, 255.0 / sixteen_bit_white);
  else
    image.convertTo(eight, CV_8U);
  if (eight.channels() == 2) cv::extractChannel(eight, eight, 0);  // gray + alpha
  const int have = eight.channels();
  if (have == channels) return eight;
  cv::Mat out;
  if (channels == 1)
    cv::cvtColor(eight, out, have == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  else if (have == 1)
    cv::cvtColor(eight, out, cv::COLOR_GRAY2BGR);
  else
    cv::cvtColor(eight, out, cv::COLOR_BGRA2BGR);
  return out;
}

std::optional<FrameImage> FrameImage::Read(const std::string& path, int channels, int sixteen_bit_white,
                                           std::string* problem, int64_t max_pixels) {
  const std::optional<ImageHeader> header = ReadImageHeader(path, problem);
  if (!header) return std::nullopt;
  return Read(path, *header, channels, sixteen_bit_white, problem, max_pixels);
}

std::optional<FrameImage> FrameImage::Read(const std::string& path, const ImageHeader& header, int channels,
                                           int sixteen_bit_white, std::string* problem, int64_t max_pixels) {
  std::optional<std::vector<unsigned char>> read = ReadImageBytes(path, header, max_pixels, problem);
  if (!read) return std::nullopt;
  std::vector<unsigned char>& bytes = *read;
  FrameImage image;
  image.path_ = path;
  image.channels_ = channels;
  if (IsJpeg(bytes)) {
    if (LooksTruncated(bytes)) {
      *problem = "truncated JPEG (no end-of-image marker)";
      return std::nullopt;
    }
    JpegReader reader(bytes);
    if (setjmp(reader.errors_.jump)) {
      *problem = std::string("unreadable image: ") + reader.errors_.message;
      return std::nullopt;
    }
    jpeg_read_header(&reader.cinfo_, TRUE);
    const auto space = reader.cinfo_.jpeg_color_space;
    // Row decoding for the common kinds: 8-bit, one scan (every table it
    // needs is in the header just read, so decoding later cannot fail on
    // them; broken data only warns). Progressive and multi-scan files, CMYK
    // and the like are decoded in full through OpenCV now.
    if (reader.cinfo_.data_precision == 8 && !jpeg_has_multiple_scans(&reader.cinfo_) &&
        (space == JCS_GRAYSCALE || space == JCS_YCbCr || space == JCS_RGB)) {
      image.width_ = static_cast<int>(reader.cinfo_.image_width);
      image.height_ = static_cast<int>(reader.cinfo_.image_height);
      image.jpeg_ = std::move(bytes);
      return image;
    }
  }
  const cv::Mat raw = DecodeImageBytes(bytes, header, max_pixels, problem);
  if (raw.empty()) return std::nullopt;
  return FromMat(raw, channels, sixteen_bit_white);
}

FrameImage FrameImage::FromMat(const cv::Mat& image, int channels, int sixteen_bit_white) {
  FrameImage out;
  out.channels_ = channels;
  out.pixels_ = ToEightBit(image, channels, sixteen_bit_white);
  out.width_ = out.pixels_.cols;
  out.height_ = out.pixels_.rows;
  out.decoded_first_ = 0;
  out.decoded_last_ = out.height_ - 1;
  return out;
}

const cv::Mat& FrameImage::Rows(int first, int last) {
  first = std::max(first, 0);
  last = std::min(last, height_ - 1);
  if (first >= decoded_first_ && last <= decoded_last_) return pixels_;
  if (decoded_last_ >= decoded_first_) {  // widen to what was decoded before
    first = std::min(first, decoded_first_);
    last = std::max(last, decoded_last_);
  }
  DecodeJpegRows(first, last);
  decoded_first_ = first;
  decoded_last_ = last;
  return pixels_;
}

void FrameImage::DecodeJpegRows(int first, int last) {
  if (jpeg_.empty()) throw std::logic_error("FrameImage " + path_ + ": rows asked of a released frame");
  pixels_.create(height_, width_, channels_ == 1 ? CV_8UC1 : CV_8UC3);
  JpegReader reader(jpeg_);
  jpeg_decompress_struct& c = reader.cinfo_;
  if (setjmp(reader.errors_.jump))
    throw InputError(path_, 0, "image", std::string("unreadable image: ") + reader.errors_.message);
  jpeg_read_header(&c, TRUE);
  // libjpeg-turbo converts to what the map needs: the luma of a colour
  // frame for a gray map, BGR (OpenCV's order) for a colour one.
  c.out_color_space = channels_ == 1 ? JCS_GRAYSCALE : JCS_EXT_BGR;
  jpeg_start_decompress(&c);
  auto read_to = [&](int last) {
    while (static_cast<int>(c.output_scanline) <= last) {
      JSAMPROW row = pixels_.ptr<unsigned char>(static_cast<int>(c.output_scanline));
      if (jpeg_read_scanlines(&c, &row, 1) != 1)  // rows the map needs must not be left undecoded
        throw InputError(path_, 0, "image",
                         "unreadable image: JPEG data stops at row " + std::to_string(c.output_scanline));
    }
  };
  // Rows above the band are skipped without the inverse DCT (a third of the
  // cost of decoding them). The skip starts at row 0: libjpeg-turbo 2.1
  // hands back wrong rows after a skip that starts inside a row group.
  if (first > 0) jpeg_skip_scanlines(&c, static_cast<JDIMENSION>(first));
  read_to(last);
  jpeg_abort_decompress(&c);  // the rows below are not needed
}

void FrameImage::Release() {
  pixels_.release();
  std::vector<unsigned char>().swap(jpeg_);
  decoded_first_ = 0;
  decoded_last_ = -1;
}

}  // namespace seamap
