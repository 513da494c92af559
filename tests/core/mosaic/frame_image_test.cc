#include "core/mosaic/frame_image.h"

#include <sys/stat.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/util/error.h"
#include "tests/testing/hostile_png.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

cv::Mat Texture(int w, int h, int type) {
  cv::Mat m(h, w, type);
  cv::randu(m, 0, 255);
  cv::GaussianBlur(m, m, {5, 5}, 1.5);
  return m;
}

TEST(FrameImage, JpegRowsDecodedAloneEqualTheFullDecode) {
  TempDir dir;
  const std::string path = (dir / "frame.jpg").string();
  cv::imwrite(path, Texture(200, 150, CV_8UC1), {cv::IMWRITE_JPEG_QUALITY, 95});
  const cv::Mat reference = cv::imread(path, cv::IMREAD_GRAYSCALE);
  std::string problem;
  auto image = FrameImage::Read(path, 1, 65535, &problem);
  ASSERT_TRUE(image) << problem;
  EXPECT_EQ(image->width(), 200);
  EXPECT_EQ(image->height(), 150);
  const cv::Mat& band = image->Rows(61, 90);
  EXPECT_EQ(cv::norm(band.rowRange(61, 91), reference.rowRange(61, 91), cv::NORM_INF), 0);
  // Asking for more decodes more; the whole frame equals OpenCV's decode.
  EXPECT_EQ(cv::norm(image->Full(), reference, cv::NORM_INF), 0);
}

TEST(FrameImage, JpegRowsFromAnywhereEqualTheFullDecode) {
  // Many random bands, starting and ending on odd and even rows, each decoded
  // afresh: its rows equal the whole frame's. For a gray frame, and a colour
  // one with 4:2:0 chroma (16-row groups) read as gray and as colour.
  TempDir dir;
  const std::string gray_path = (dir / "gray.jpg").string(), colour_path = (dir / "colour.jpg").string();
  cv::imwrite(gray_path, Texture(200, 150, CV_8UC1), {cv::IMWRITE_JPEG_QUALITY, 90});
  cv::imwrite(colour_path, Texture(200, 150, CV_8UC3), {cv::IMWRITE_JPEG_QUALITY, 90});  // 4:2:0, libjpeg's default
  for (const auto& [path, channels] :
       std::vector<std::pair<std::string, int>>{{gray_path, 1}, {colour_path, 1}, {colour_path, 3}}) {
    std::string problem;
    auto whole = FrameImage::Read(path, channels, 65535, &problem);
    ASSERT_TRUE(whole) << problem;
    const cv::Mat reference = whole->Full().clone();
    cv::RNG rng(7);
    for (int trial = 0; trial < 100; ++trial) {
      const int first = rng.uniform(-5, 150), last = first + rng.uniform(0, 60);
      auto image = FrameImage::Read(path, channels, 65535, &problem);
      const cv::Mat& decoded = image->Rows(first, last);
      const int a = std::max(first, 0), b = std::min(last, 149);
      ASSERT_EQ(cv::norm(decoded.rowRange(a, b + 1), reference.rowRange(a, b + 1), cv::NORM_INF), 0)
          << path << " as " << channels << " channels, rows " << first << "-" << last;
    }
  }
}

TEST(FrameImage, ColourJpegBecomesLumaForAGrayMapAndBgrForAColourOne) {
  TempDir dir;
  const std::string path = (dir / "frame.jpg").string();
  cv::imwrite(path, Texture(64, 48, CV_8UC3), {cv::IMWRITE_JPEG_QUALITY, 95});
  std::string problem;
  auto gray = FrameImage::Read(path, 1, 65535, &problem);
  auto colour = FrameImage::Read(path, 3, 65535, &problem);
  ASSERT_TRUE(gray && colour);
  const cv::Mat bgr = cv::imread(path, cv::IMREAD_COLOR);
  EXPECT_EQ(colour->Full().type(), CV_8UC3);
  EXPECT_LE(cv::norm(colour->Full(), bgr, cv::NORM_INF), 1);
  cv::Mat luma;
  cv::cvtColor(bgr, luma, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(gray->Full().type(), CV_8UC1);
  EXPECT_LE(cv::norm(gray->Full(), luma, cv::NORM_INF), 3);
}

TEST(FrameImage, ProgressiveJpegsAreDecodedWhole) {
  // Several scans: later tables could be missing, so no decoding by rows.
  testing::TempDir dir;
  const std::string path = (dir / "frame.jpg").string();
  cv::imwrite(path, Texture(80, 60, CV_8UC1), {cv::IMWRITE_JPEG_PROGRESSIVE, 1});
  std::string problem;
  auto image = FrameImage::Read(path, 1, 65535, &problem);
  ASSERT_TRUE(image) << problem;
  EXPECT_EQ(cv::norm(image->Rows(10, 20), cv::imread(path, cv::IMREAD_GRAYSCALE), cv::NORM_INF), 0);
}

TEST(FrameImage, OtherFormatsAndDepthsAreConverted) {
  TempDir dir;
  const std::string path = (dir / "frame.png").string();
  cv::imwrite(path, cv::Mat(10, 12, CV_16UC1, cv::Scalar(4095)));
  std::string problem;
  auto image = FrameImage::Read(path, 1, 4095, &problem);
  ASSERT_TRUE(image) << problem;
  EXPECT_EQ(image->Full().type(), CV_8UC1);
  EXPECT_EQ(image->Full().at<uint8_t>(3, 3), 255);
}

TEST(FrameImage, BrokenFilesAreReportedNotDecoded) {
  TempDir dir;
  std::string problem;
  EXPECT_FALSE(FrameImage::Read((dir / "none.jpg").string(), 1, 65535, &problem));
  EXPECT_EQ(problem, "missing image");

  const std::string path = (dir / "frame.jpg").string();
  cv::imwrite(path, Texture(64, 48, CV_8UC1));
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream((dir / "cut.jpg").string(), std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  EXPECT_FALSE(FrameImage::Read((dir / "cut.jpg").string(), 1, 65535, &problem));
  EXPECT_NE(problem.find("truncated JPEG"), std::string::npos);

  // A JPEG header that libjpeg refuses, and bytes that are no image at all.
  std::string bad = bytes;
  bad[bytes.find("\xFF\xC0") + 5] = 0;  // zero image height in the frame header
  bad[bytes.find("\xFF\xC0") + 6] = 0;
  std::ofstream((dir / "bad.jpg").string(), std::ios::binary) << bad;
  EXPECT_FALSE(FrameImage::Read((dir / "bad.jpg").string(), 1, 65535, &problem));
  EXPECT_NE(problem.find("unreadable image"), std::string::npos) << problem;
  std::ofstream((dir / "text.png").string()) << "not an image";
  EXPECT_FALSE(FrameImage::Read((dir / "text.png").string(), 1, 65535, &problem));
  EXPECT_EQ(problem, "unreadable image");
}

// The guard of core/image/image_read.h: huge claims and FIFOs are refused unread.
TEST(FrameImage, HugeImagesAndFifosAreRefusedUnread) {
  TempDir dir;
  const std::string claiming = (dir / "claims.png").string(), fifo = (dir / "fifo.png").string();
  testing::WriteBytes(claiming, testing::ClaimingPng(30000, 30000));
  std::string problem;
  EXPECT_FALSE(FrameImage::Read(claiming, 1, 65535, &problem));
  EXPECT_EQ(problem.rfind("image too large", 0), 0u) << problem;
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_FALSE(FrameImage::Read(fifo, 1, 65535, &problem));
  EXPECT_EQ(problem, "not a regular file: a FIFO, skipped unread");
}

TEST(FrameImage, ToEightBitHandlesDepthsAndChannels) {
  cv::Mat sixteen(2, 2, CV_16U, cv::Scalar(65535));
  EXPECT_EQ(ToEightBit(sixteen, 1, 65535).at<uint8_t>(0, 0), 255);
  EXPECT_EQ(ToEightBit(sixteen, 1, 4095).type(), CV_8U);
  cv::Mat bgr(2, 2, CV_8UC3, cv::Scalar(10, 10, 10));
  EXPECT_EQ(ToEightBit(bgr, 1, 65535).type(), CV_8UC1);
  cv::Mat gray_alpha(2, 2, CV_8UC2, cv::Scalar(7, 255));
  EXPECT_EQ(ToEightBit(gray_alpha, 3, 65535).type(), CV_8UC3);
}

}  // namespace
}  // namespace seamap
