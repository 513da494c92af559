#include "core/tiles/tile_codec.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

// A gray+alpha tile with a gradient, fully transparent left quarter and
// partly transparent band, so every alpha case is present.
cv::Mat GrayAlphaTile() {
  cv::Mat tile(256, 256, CV_8UC2);
  for (int r = 0; r < 256; ++r)
    for (int c = 0; c < 256; ++c)
      tile.at<cv::Vec2b>(r, c) = {static_cast<uint8_t>((r + 3 * c) & 255),
                                  static_cast<uint8_t>(c < 64 ? 0 : (c < 128 ? r : 255))};
  return tile;
}

cv::Mat BgraTile() {
  cv::Mat tile(256, 256, CV_8UC4);
  for (int r = 0; r < 256; ++r)
    for (int c = 0; c < 256; ++c)
      tile.at<cv::Vec4b>(r, c) = {static_cast<uint8_t>(r), static_cast<uint8_t>(c), static_cast<uint8_t>((r * c) & 255),
                                  static_cast<uint8_t>(c < 64 ? 0 : (c < 128 ? r : 255))};
  return tile;
}

bool SameMat(const cv::Mat& a, const cv::Mat& b) {
  return a.type() == b.type() && a.size() == b.size() && cv::norm(a, b, cv::NORM_INF) == 0;
}

int PngColorType(const std::vector<uint8_t>& png) {
  return png.at(25);
}

TEST(TileCodec, ParsesFormatNames) {
  EXPECT_EQ(ParseTileFormat("png", "cfg"), TileFormat::kPng);
  EXPECT_EQ(ParseTileFormat("JPG", "cfg"), TileFormat::kJpeg);
  EXPECT_EQ(ParseTileFormat("jpeg", "cfg"), TileFormat::kJpeg);
  EXPECT_EQ(ParseTileFormat("webp", "cfg"), TileFormat::kWebp);
  EXPECT_EQ(TileExtension(TileFormat::kJpeg), "jpg");
  EXPECT_EQ(TileExtension(TileFormat::kWebp), "webp");
  EXPECT_EQ(TileMimeType(TileFormat::kPng), "image/png");
  EXPECT_EQ(TileMimeType(TileFormat::kJpeg), "image/jpeg");
  EXPECT_EQ(TileMimeType(TileFormat::kWebp), "image/webp");
}

TEST(TileCodec, UnknownFormatNamesSourceAndField) {
  try {
    ParseTileFormat("tiff", "mission.json");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "mission.json");
    EXPECT_EQ(e.field(), "tile_format");
    EXPECT_NE(std::string(e.what()).find("tiff"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("webp"), std::string::npos);
  }
}

TEST(TileCodec, GrayAlphaPngIsExactAndTwoChannel) {
  const cv::Mat tile = GrayAlphaTile();
  const std::vector<uint8_t> png = EncodeTile(tile, {});
  EXPECT_EQ(PngColorType(png), 4);  // PNG gray+alpha
  EXPECT_TRUE(SameMat(DecodeTile(png), tile));
}

TEST(TileCodec, BgraPngIsExact) {
  const cv::Mat tile = BgraTile();
  const std::vector<uint8_t> png = EncodeTile(tile, {});
  EXPECT_EQ(PngColorType(png), 6);  // RGBA
  EXPECT_TRUE(SameMat(DecodeTile(png), tile));
}

TEST(TileCodec, OpaqueTilesDropAlphaAndDecodeOpaque) {
  cv::Mat gray(256, 256, CV_8UC2, cv::Scalar(90, 255));
  gray(cv::Rect(10, 10, 50, 50)).setTo(cv::Scalar(200, 255));
  const std::vector<uint8_t> gray_png = EncodeTile(gray, {});
  EXPECT_EQ(PngColorType(gray_png), 0);  // plain gray
  EXPECT_TRUE(SameMat(DecodeTile(gray_png), gray));

  cv::Mat bgra(256, 256, CV_8UC4, cv::Scalar(10, 20, 30, 255));
  const std::vector<uint8_t> rgb_png = EncodeTile(bgra, {});
  EXPECT_EQ(PngColorType(rgb_png), 2);  // RGB
  EXPECT_TRUE(SameMat(DecodeTile(rgb_png), bgra));
}

TEST(TileCodec, OneTranslucentPixelKeepsAlpha) {
  // White colour bytes must not pass for alpha, and the last pixel of a row
  // of a tile cut from a larger image counts like any other.
  cv::Mat big_gray(300, 300, CV_8UC2, cv::Scalar(255, 255)),
      big_bgra(300, 300, CV_8UC4, cv::Scalar(255, 128, 255, 255));
  cv::Mat gray = big_gray(cv::Rect(20, 20, 256, 256)), bgra = big_bgra(cv::Rect(20, 20, 256, 256));
  gray.at<cv::Vec2b>(100, 255) = {255, 254};
  bgra.at<cv::Vec4b>(255, 0) = {255, 128, 255, 0};
  EXPECT_EQ(PngColorType(EncodeTile(gray, {})), 4);  // gray+alpha
  EXPECT_EQ(PngColorType(EncodeTile(bgra, {})), 6);  // RGBA
  EXPECT_TRUE(SameMat(DecodeTile(EncodeTile(gray, {})), gray));
  EXPECT_TRUE(SameMat(DecodeTile(EncodeTile(bgra, {})), bgra));
  gray.at<cv::Vec2b>(100, 255) = {0, 255};
  EXPECT_EQ(PngColorType(EncodeTile(gray, {})), 0);  // opaque again: plain gray
  EXPECT_TRUE(SameMat(DecodeTile(EncodeTile(gray, {})), gray));
}

TEST(TileCodec, EveryPngLevelIsLosslessForEveryLayout) {
  cv::Mat opaque_gray(256, 256, CV_8UC2, cv::Scalar(0, 255)), opaque_bgr(256, 256, CV_8UC4, cv::Scalar(0, 0, 0, 255));
  cv::randu(opaque_gray.reshape(1), 0, 255);
  opaque_gray.forEach<cv::Vec2b>([](cv::Vec2b& p, const int*) { p[1] = 255; });
  cv::randu(opaque_bgr, 0, 255);
  opaque_bgr.forEach<cv::Vec4b>([](cv::Vec4b& p, const int*) { p[3] = 255; });
  for (int level = 0; level <= 9; ++level) {
    TileEncoding enc;
    enc.png_level = level;
    for (const cv::Mat& tile : {GrayAlphaTile(), BgraTile(), opaque_gray, opaque_bgr})
      EXPECT_TRUE(SameMat(DecodeTile(EncodeTile(tile, enc)), tile))
          << "level " << level << ", " << tile.channels() << " channels";
  }
}

TEST(TileCodec, PngLevelChangesSize) {
  const cv::Mat tile = BgraTile();
  TileEncoding fast, small;
  fast.png_level = 0;
  small.png_level = 9;
  EXPECT_GT(EncodeTile(tile, fast).size(), EncodeTile(tile, small).size());
}

TEST(TileCodec, FastPngIsAtMostAQuarterLargerThanZlibDefault) {
  // A seabed-like tile: smooth texture plus fine grain, partly transparent.
  cv::Mat gray(256, 256, CV_8U), grain(256, 256, CV_8U);
  cv::randu(gray, 0, 255);
  cv::GaussianBlur(gray, gray, cv::Size(0, 0), 3);
  cv::normalize(gray, gray, 30, 220, cv::NORM_MINMAX);
  cv::randn(grain, 0, 6);
  gray += grain;
  cv::Mat alpha(256, 256, CV_8U, cv::Scalar(255));
  alpha(cv::Rect(0, 0, 256, 40)) = 0;
  gray.setTo(0, alpha == 0);
  cv::Mat tile;
  cv::merge(std::vector<cv::Mat>{gray, alpha}, tile);
  TileEncoding fast, standard;
  fast.png_level = 1;
  standard.png_level = 6;
  const size_t fast_size = EncodeTile(tile, fast).size(), standard_size = EncodeTile(tile, standard).size();
  EXPECT_LE(fast_size, standard_size * 5 / 4) << fast_size << " vs " << standard_size;
  EXPECT_TRUE(SameMat(DecodeTile(EncodeTile(tile, fast)), tile));
}

TEST(TileCodec, JpegPaintsBackgroundUnderTransparentPixels) {
  cv::Mat tile(256, 256, CV_8UC4, cv::Scalar(0, 0, 255, 255));     // opaque red
  tile(cv::Rect(0, 0, 128, 256)).setTo(cv::Scalar(0, 0, 255, 0));  // transparent red
  TileEncoding enc;
  enc.format = TileFormat::kJpeg;
  enc.jpeg_quality = 95;
  enc.background = cv::Scalar(200, 120, 40);
  const cv::Mat out = DecodeTile(EncodeTile(tile, enc));
  ASSERT_EQ(out.type(), CV_8UC4);
  const cv::Vec4b left = out.at<cv::Vec4b>(128, 40), right = out.at<cv::Vec4b>(128, 200);
  EXPECT_NEAR(left[0], 200, 6);
  EXPECT_NEAR(left[1], 120, 6);
  EXPECT_NEAR(left[2], 40, 6);
  EXPECT_EQ(left[3], 255);
  EXPECT_NEAR(right[0], 0, 6);
  EXPECT_NEAR(right[2], 255, 6);
}

TEST(TileCodec, GrayJpegStaysGrayWithBackgroundLuminance) {
  cv::Mat tile(256, 256, CV_8UC2, cv::Scalar(30, 0));  // all transparent
  tile(cv::Rect(128, 0, 128, 256)).setTo(cv::Scalar(180, 255));
  TileEncoding enc;
  enc.format = TileFormat::kJpeg;
  enc.background = cv::Scalar(255, 255, 255);
  const std::vector<uint8_t> jpg = EncodeTile(tile, enc);
  const cv::Mat out = DecodeTile(jpg);
  ASSERT_EQ(out.type(), CV_8UC2);
  EXPECT_NEAR(out.at<cv::Vec2b>(100, 40)[0], 255, 3);
  EXPECT_NEAR(out.at<cv::Vec2b>(100, 200)[0], 180, 3);
  EXPECT_EQ(out.at<cv::Vec2b>(100, 40)[1], 255);
}

TEST(TileCodec, WebpKeepsAlphaApproximately) {
  cv::Mat tile = BgraTile();  // smooth colours: lossy WebP is meant for photos
  for (int r = 0; r < 256; ++r)
    for (int c = 0; c < 256; ++c) tile.at<cv::Vec4b>(r, c)[2] = static_cast<uint8_t>(255 - r);
  TileEncoding enc;
  enc.format = TileFormat::kWebp;
  enc.webp_quality = 90;
  const cv::Mat out = DecodeTile(EncodeTile(tile, enc));
  ASSERT_EQ(out.type(), CV_8UC4);
  std::vector<cv::Mat> in_ch, out_ch;
  cv::split(tile, in_ch);
  cv::split(out, out_ch);
  EXPECT_LE(cv::norm(in_ch[3], out_ch[3], cv::NORM_INF), 2);  // WebP alpha is lossless by default
  const cv::Rect opaque(160, 0, 96, 256);
  EXPECT_LT(cv::norm(tile(opaque), out(opaque), cv::NORM_L1) / (opaque.area() * 4.0), 8.0);
}

TEST(TileCodec, LosslessWebpOfGrayAlphaDecodesAsGray) {
  const cv::Mat tile = GrayAlphaTile();
  TileEncoding enc;
  enc.format = TileFormat::kWebp;
  enc.webp_quality = 101;
  const cv::Mat out = DecodeTile(EncodeTile(tile, enc));
  ASSERT_EQ(out.type(), CV_8UC2);
  // WebP may drop colour under fully transparent pixels; compare the visible ones.
  const cv::Rect visible(64, 0, 192, 256);
  std::vector<cv::Mat> in_ch, out_ch;
  cv::split(tile, in_ch);
  cv::split(out, out_ch);
  EXPECT_EQ(cv::norm(in_ch[1], out_ch[1], cv::NORM_INF), 0);
  cv::Mat nonzero = in_ch[1](visible) > 0;
  cv::Mat diff;
  cv::absdiff(in_ch[0](visible), out_ch[0](visible), diff);
  diff.setTo(0, ~nonzero);
  EXPECT_EQ(cv::countNonZero(diff), 0);
}

TEST(TileCodec, RejectsBadInput) {
  EXPECT_THROW(EncodeTile(cv::Mat(8, 8, CV_8UC3), {}), std::invalid_argument);
  EXPECT_THROW(DecodeTile({1, 2, 3, 4}), std::runtime_error);
  EXPECT_THROW(DecodeTile({}), std::runtime_error);
}

TEST(TileCodec, WithColourChannelsConvertsAndKeepsAlpha) {
  cv::Mat gray(2, 2, CV_8UC2, cv::Scalar(90, 128));
  cv::Mat colour = WithColourChannels(gray, 3);
  ASSERT_EQ(colour.type(), CV_8UC4);
  EXPECT_EQ(colour.at<cv::Vec4b>(1, 1), cv::Vec4b(90, 90, 90, 128));
  cv::Mat back = WithColourChannels(colour, 1);
  ASSERT_EQ(back.type(), CV_8UC2);
  EXPECT_EQ(back.at<cv::Vec2b>(0, 0), cv::Vec2b(90, 128));
  EXPECT_EQ(WithColourChannels(gray, 1).data, gray.data);  // already right: no copy
}

}  // namespace
}  // namespace seamap
