#include "core/tiles/tile_codec.h"

#include <libdeflate.h>
#include <png.h>

#include <algorithm>
#include <memory>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

constexpr uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

// Every pixel's alpha (the last byte of each 2- or 4-byte pixel) is 255: an
// AND over whole pixels, which vectorises (OpenCV's channel extraction
// and minimum took 6 instructions a pixel).
template <typename Pixel>
bool AlphaAllOpaque(const cv::Mat& tile) {
  Pixel alpha = 0;  // the alpha byte's bits, whatever the byte order
  reinterpret_cast<uint8_t*>(&alpha)[sizeof(Pixel) - 1] = 0xFF;
  for (int r = 0; r < tile.rows; ++r) {
    const Pixel* px = tile.ptr<Pixel>(r);
    Pixel all = alpha;
    for (int c = 0; c < tile.cols; ++c) all &= px[c];
    if ((all & alpha) != alpha) return false;
  }
  return true;
}

bool FullyOpaque(const cv::Mat& tile) {
  return tile.channels() == 2 ? AlphaAllOpaque<uint16_t>(tile) : AlphaAllOpaque<uint32_t>(tile);
}

// The gray channel of a gray+alpha tile, by a loop the compiler vectorises.
cv::Mat GrayOf(const cv::Mat& tile) {
  cv::Mat out(tile.size(), CV_8UC1);
  for (int r = 0; r < tile.rows; ++r) {
    const uint8_t* src = tile.ptr<uint8_t>(r);
    uint8_t* dst = out.ptr<uint8_t>(r);
    for (int c = 0; c < tile.cols; ++c) dst[c] = src[2 * c];
  }
  return out;
}

// Colour channels only (gray or BGR), dropping alpha.
cv::Mat WithoutAlpha(const cv::Mat& tile) {
  if (tile.channels() == 2) return GrayOf(tile);
  cv::Mat out;
  cv::cvtColor(tile, out, cv::COLOR_BGRA2BGR);
  return out;
}

// Paints the tile over `background`: JPEG cannot store transparency.
cv::Mat CompositeOver(const cv::Mat& tile, const cv::Scalar& background) {
  const int colours = tile.channels() - 1;
  cv::Scalar bg = background;
  if (colours == 1) {  // gray tile: the background's luminance
    cv::Mat px(1, 1, CV_8UC3, background), gray;
    cv::cvtColor(px, gray, cv::COLOR_BGR2GRAY);
    bg = cv::Scalar(gray.at<uint8_t>(0, 0));
  }
  cv::Mat out(tile.size(), CV_8UC(colours));
  for (int r = 0; r < tile.rows; ++r) {
    const uint8_t* src = tile.ptr<uint8_t>(r);
    uint8_t* dst = out.ptr<uint8_t>(r);
    for (int c = 0; c < tile.cols; ++c, src += colours + 1, dst += colours) {
      const int a = src[colours];
      for (int k = 0; k < colours; ++k) {
        const int b = cv::saturate_cast<uint8_t>(bg[k]);
        dst[k] = static_cast<uint8_t>((src[k] * a + b * (255 - a) + 127) / 255);
      }
    }
  }
  return out;
}

// PNG colour type of a tile with 1 (gray), 2 (gray, alpha), 3 or 4 (colour, alpha) channels.
int PngColorTypeOf(int channels) {
  return channels == 2   ? PNG_COLOR_TYPE_GRAY_ALPHA
         : channels == 3 ? PNG_COLOR_TYPE_RGB
         : channels == 4 ? PNG_COLOR_TYPE_RGB_ALPHA
                         : PNG_COLOR_TYPE_GRAY;
}

// The tile in PNG's channel order: gray, gray+alpha, RGB or RGBA (alpha
// dropped when every pixel is opaque), converted in one pass.
cv::Mat InPngOrder(const cv::Mat& tile, bool opaque) {
  if (tile.channels() == 2) return opaque ? GrayOf(tile) : tile;
  cv::Mat out;
  cv::cvtColor(tile, out, opaque ? cv::COLOR_BGRA2RGB : cv::COLOR_BGRA2RGBA);
  return out;
}

// PNG levels 0 and 6-9 through libpng directly: OpenCV cannot write
// 2-channel (gray+alpha) PNGs, and its adaptive filter choice costs 3x the
// time. The fast levels are EncodePngFast's. Both take the tile InPngOrder.
std::vector<uint8_t> EncodePng(const cv::Mat& tile, int level) {
  const int color_type = PngColorTypeOf(tile.channels());
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!info) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("libpng: out of memory");
  }
  std::vector<uint8_t> out;
  cv::Mat rows = tile.isContinuous() ? tile : tile.clone();
  std::vector<png_bytep> row_ptrs(rows.rows);
  for (int r = 0; r < rows.rows; ++r) row_ptrs[r] = rows.ptr<png_byte>(r);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("libpng: cannot encode tile");
  }
  png_set_write_fn(
      png, &out,
      [](png_structp p, png_bytep data, png_size_t n) {
        auto* buf = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(p));
        buf->insert(buf->end(), data, data + n);
      },
      nullptr);
  png_set_compression_level(png, level);
  png_set_IHDR(png, info, rows.cols, rows.rows, 8, color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_set_rows(png, info, row_ptrs.data());
  png_write_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_destroy_write_struct(&png, &info);
  return out;
}

// The fast PNG levels (1-5): the Average filter (on seabed tiles nearly as
// small as Paeth and a quarter faster), compressed in one call by libdeflate
// (5.6x faster than zlib level 6 for 5 % more bytes; libpng can only use
// zlib, so the few PNG chunks are written here).
std::vector<uint8_t> EncodePngFast(const cv::Mat& tile, int level) {
  const int channels = tile.channels(), width = tile.cols, height = tile.rows;
  const int color_type = PngColorTypeOf(channels);
  const size_t row_bytes = static_cast<size_t>(width) * channels;
  // Filtered scanlines: a filter-type byte (3, Average) then the differences.
  thread_local std::vector<uint8_t> filtered, zero_row;
  filtered.resize((row_bytes + 1) * height);
  zero_row.assign(row_bytes, 0);
  const uint8_t* up = nullptr;
  for (int y = 0; y < height; ++y) {
    const uint8_t* raw = tile.ptr<uint8_t>(y);
    uint8_t* __restrict out = &filtered[(row_bytes + 1) * y];
    out[0] = 3;
    ++out;
    // Average of the raw bytes to the left and above: no dependence between
    // outputs, so the main loop vectorises.
    const uint8_t* __restrict above = up ? up : zero_row.data();
    for (int i = 0; i < channels; ++i) out[i] = static_cast<uint8_t>(raw[i] - (above[i] >> 1));
    for (size_t i = channels; i < row_bytes; ++i)
      out[i] = static_cast<uint8_t>(raw[i] - ((raw[i - channels] + above[i]) >> 1));
    up = raw;
  }
  // One compressor per thread and level: making one allocates its tables.
  struct FreeCompressor {
    void operator()(libdeflate_compressor* c) const { libdeflate_free_compressor(c); }
  };
  thread_local std::unique_ptr<libdeflate_compressor, FreeCompressor> compressors[5];
  level = std::clamp(level, 1, 5);
  auto& slot = compressors[level - 1];
  if (!slot) slot.reset(libdeflate_alloc_compressor(level));
  libdeflate_compressor* compressor = slot.get();
  if (!compressor) throw std::runtime_error("libdeflate: out of memory");
  // Signature, IHDR chunk, IDAT's length and type, its data, its CRC, IEND.
  const size_t bound = libdeflate_zlib_compress_bound(compressor, filtered.size());
  std::vector<uint8_t> out(8 + 25 + 8 + bound + 4 + 12);
  const size_t idat = libdeflate_zlib_compress(compressor, filtered.data(), filtered.size(), &out[8 + 25 + 8], bound);
  if (idat == 0) throw std::runtime_error("libdeflate: cannot compress tile");
  auto put32 = [](uint8_t* p, uint32_t v) {
    p[0] = static_cast<uint8_t>(v >> 24);
    p[1] = static_cast<uint8_t>(v >> 16);
    p[2] = static_cast<uint8_t>(v >> 8);
    p[3] = static_cast<uint8_t>(v);
  };
  // A chunk at p: length, type, data (already in place), CRC of type and data.
  auto chunk = [&](uint8_t* p, const char* type, uint32_t length) {
    put32(p, length);
    std::copy(type, type + 4, p + 4);
    put32(p + 8 + length, libdeflate_crc32(0, p + 4, 4 + length));
    return p + 12 + length;
  };
  std::copy(kPngSignature, kPngSignature + 8, out.data());
  uint8_t* ihdr = out.data() + 8;
  put32(ihdr + 8, static_cast<uint32_t>(width));
  put32(ihdr + 12, static_cast<uint32_t>(height));
  ihdr[16] = 8;  // bit depth
  ihdr[17] = static_cast<uint8_t>(color_type);
  ihdr[18] = ihdr[19] = ihdr[20] = 0;  // deflate, adaptive filtering, no interlace
  uint8_t* next = chunk(ihdr, "IHDR", 13);
  next = chunk(next, "IDAT", static_cast<uint32_t>(idat));
  next = chunk(next, "IEND", 0);
  out.resize(next - out.data());
  return out;
}

std::vector<uint8_t> Encode(const std::string& ext, const cv::Mat& img, const std::vector<int>& params) {
  std::vector<uint8_t> out;
  if (!cv::imencode(ext, img, out, params)) throw std::runtime_error("cannot encode tile as " + ext.substr(1));
  return out;
}

// PNG colour type from the IHDR chunk, or -1 when the bytes are not a PNG.
int PngColorType(const std::vector<uint8_t>& bytes) {
  if (bytes.size() < 26 || !std::equal(kPngSignature, kPngSignature + 8, bytes.begin())) return -1;
  return bytes[25];
}

bool ColoursEqual(const cv::Mat& bgra) {
  for (int r = 0; r < bgra.rows; ++r) {
    const cv::Vec4b* px = bgra.ptr<cv::Vec4b>(r);
    for (int c = 0; c < bgra.cols; ++c)
      if (px[c][0] != px[c][1] || px[c][0] != px[c][2]) return false;
  }
  return true;
}

}  // namespace

TileFormat ParseTileFormat(const std::string& name, const std::string& source) {
  std::string lower = name;
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (lower == "png") return TileFormat::kPng;
  if (lower == "jpg" || lower == "jpeg") return TileFormat::kJpeg;
  if (lower == "webp") return TileFormat::kWebp;
  throw InputError(source, 0, "tile_format", "unknown tile format '" + name + "', expected png, jpg, jpeg or webp");
}

std::string TileExtension(TileFormat f) {
  switch (f) {
    case TileFormat::kJpeg:
      return "jpg";
    case TileFormat::kWebp:
      return "webp";
    default:
      return "png";
  }
}

std::string TileMimeType(TileFormat f) {
  switch (f) {
    case TileFormat::kJpeg:
      return "image/jpeg";
    case TileFormat::kWebp:
      return "image/webp";
    default:
      return "image/png";
  }
}

std::vector<uint8_t> EncodeTile(const cv::Mat& tile, const TileEncoding& enc) {
  if (tile.depth() != CV_8U || (tile.channels() != 2 && tile.channels() != 4))
    throw std::invalid_argument("EncodeTile expects CV_8UC2 or CV_8UC4");
  switch (enc.format) {
    case TileFormat::kJpeg:
      return Encode(".jpg", CompositeOver(tile, enc.background), {cv::IMWRITE_JPEG_QUALITY, enc.jpeg_quality});
    case TileFormat::kWebp: {
      // Opaque tiles drop alpha: smaller, and WebP decodes them as opaque.
      cv::Mat img = FullyOpaque(tile) ? WithoutAlpha(tile) : WithColourChannels(tile, 3);
      if (img.channels() == 1) cv::cvtColor(img, img, cv::COLOR_GRAY2BGR);
      return Encode(".webp", img, {cv::IMWRITE_WEBP_QUALITY, enc.webp_quality});
    }
    default: {
      const cv::Mat img = InPngOrder(tile, FullyOpaque(tile));
      return enc.png_level >= 1 && enc.png_level <= 5 ? EncodePngFast(img, enc.png_level)
                                                      : EncodePng(img, enc.png_level);
    }
  }
}

cv::Mat DecodeTile(const std::vector<uint8_t>& bytes) {
  cv::Mat img = bytes.empty() ? cv::Mat() : cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  if (img.empty()) throw std::runtime_error("cannot decode tile image data");
  if (img.depth() != CV_8U) img.convertTo(img, CV_8U, 1.0 / 257);  // 16-bit PNGs
  const int color_type = PngColorType(bytes);
  cv::Mat out;
  switch (img.channels()) {
    case 1: {
      cv::Mat opaque(img.size(), CV_8UC1, cv::Scalar(255));
      cv::merge(std::vector<cv::Mat>{img, opaque}, out);
      return out;
    }
    case 3:
      cv::cvtColor(img, out, cv::COLOR_BGR2BGRA);
      break;
    default:
      out = img;
      break;
  }
  // Gray data (a gray PNG, or colour channels all equal) comes back as gray+alpha.
  if (color_type == PNG_COLOR_TYPE_GRAY_ALPHA || ColoursEqual(out)) {
    cv::Mat gray(out.size(), CV_8UC2);
    const int from_to[] = {0, 0, 3, 1};
    cv::mixChannels(&out, 1, &gray, 1, from_to, 2);
    return gray;
  }
  return out;
}

cv::Mat WithColourChannels(const cv::Mat& tile, int colour_channels) {
  if (tile.channels() == colour_channels + 1) return tile;
  cv::Mat out(tile.size(), CV_8UC(colour_channels + 1));
  if (colour_channels == 3) {  // gray+alpha -> BGRA
    const int from_to[] = {0, 0, 0, 1, 0, 2, 1, 3};
    cv::mixChannels(&tile, 1, &out, 1, from_to, 4);
  } else {  // BGRA -> gray+alpha
    cv::Mat gray;
    cv::cvtColor(tile, gray, cv::COLOR_BGRA2GRAY);
    const cv::Mat in[] = {gray, tile};
    const int from_to[] = {0, 0, 4, 1};
    cv::mixChannels(in, 2, &out, 1, from_to, 2);
  }
  return out;
}

}  // namespace seamap
