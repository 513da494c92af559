#include "core/image/image_header.h"

#include <sys/stat.h>

#include <random>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "core/image/image_read.h"
#include "core/util/process_stats.h"
#include "tests/testing/hostile_png.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

// Every format surveys use, gray and colour, written by OpenCV: the header
// says what decoding gives.
TEST(ImageHeader, SaysWhatDecodingGives) {
  TempDir dir;
  cv::Mat gray(37, 53, CV_8UC1), colour(37, 53, CV_8UC3), gray16(37, 53, CV_16UC1);
  cv::randu(gray, 0, 255);
  cv::randu(colour, 0, 255);
  cv::randu(gray16, 0, 65535);
  int checked = 0;
  for (const std::string ext : {".png", ".jpg", ".tif", ".bmp", ".webp"}) {
    for (const cv::Mat* m : {&gray, &colour, &gray16}) {
      if (m == &gray16 && ext != ".png" && ext != ".tif") continue;
      const std::string path = (dir / ("f" + std::to_string(checked) + ext)).string();
      ASSERT_TRUE(cv::imwrite(path, *m)) << path;
      std::string problem;
      const auto header = ReadImageHeader(path, &problem);
      ASSERT_TRUE(header) << path << ": " << problem;
      const cv::Mat decoded = cv::imread(path, cv::IMREAD_UNCHANGED);
      EXPECT_EQ(header->width, decoded.cols) << path;
      EXPECT_EQ(header->height, decoded.rows) << path;
      if (header->channels != 0) {
        EXPECT_EQ(header->channels, decoded.channels()) << path;
      }
      EXPECT_NE(header->format, "") << path;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 12);
}

TEST(ImageHeader, JpegFrameHeaderAfterLargeSegments) {
  TempDir dir;
  cv::Mat colour(20, 30, CV_8UC3, cv::Scalar(10, 200, 30));
  std::vector<unsigned char> jpeg;
  cv::imencode(".jpg", colour, jpeg);
  // Three 60 KB application segments (like EXIF thumbnails) before the frame header.
  std::string bytes(jpeg.begin(), jpeg.begin() + 2);
  for (int i = 0; i < 3; ++i) {
    const int length = 60000;
    bytes += std::string{'\xFF', '\xE5', static_cast<char>(length >> 8), static_cast<char>(length & 0xFF)};
    bytes += std::string(length - 2, 'x');
  }
  bytes.append(jpeg.begin() + 2, jpeg.end());
  const std::string path = (dir / "exif.jpg").string();
  testing::WriteBytes(path, bytes);
  std::string problem;
  const auto header = ReadImageHeader(path, &problem);
  ASSERT_TRUE(header) << problem;
  EXPECT_EQ(header->width, 30);
  EXPECT_EQ(header->height, 20);
  EXPECT_EQ(header->channels, 3);
}

TEST(ImageHeader, ZeroPngHelperWritesAValidImage) {
  TempDir dir;
  const std::string path = (dir / "zeros.png").string();
  testing::WriteBytes(path, testing::ZeroPng(301, 200));
  const cv::Mat decoded = cv::imread(path, cv::IMREAD_UNCHANGED);
  ASSERT_EQ(decoded.cols, 301);
  ASSERT_EQ(decoded.rows, 200);
  EXPECT_EQ(cv::countNonZero(decoded), 0);
}

// A header claiming 100000 x 100000 pixels, and a valid 30000 x 30000 PNG of
// zeros (875 KB that decode to 900 MB): refused with the reason, unread.
TEST(ImageHeader, HugeImagesAreRefusedBeforeDecoding) {
  TempDir dir;
  const std::string claiming = (dir / "claims.png").string(), zeros = (dir / "zeros.png").string();
  testing::WriteBytes(claiming, testing::ClaimingPng(100000, 100000));
  const std::string zero_png = testing::ZeroPng(30000, 30000);
  EXPECT_LT(zero_png.size(), 1000000u);
  testing::WriteBytes(zeros, zero_png);
  const int64_t rss_before = PeakRssBytes();
  for (const std::string& path : {claiming, zeros}) {
    std::string problem;
    const auto header = ReadImageHeader(path, &problem);
    ASSERT_TRUE(header) << problem;
    const auto why = TooLargeToDecode(*header, kDefaultMaxImagePixels);
    ASSERT_TRUE(why) << path;
    EXPECT_NE(why->find("image too large"), std::string::npos) << *why;
    EXPECT_NE(why->find("max_image_pixels"), std::string::npos) << *why;
    EXPECT_TRUE(ReadGuardedImage(path, &problem).empty()) << path;
    EXPECT_EQ(problem, *why);
  }
  EXPECT_LT(PeakRssBytes() - rss_before, int64_t{200} << 20) << "a refused image was decoded";
  // Within a raised limit the same header passes the check.
  std::string problem;
  EXPECT_FALSE(TooLargeToDecode(*ReadImageHeader(zeros, &problem), 1'000'000'000));
}

TEST(ImageHeader, FifosAndFoldersAreNotReadButNamed) {
  TempDir dir;
  const std::string fifo = (dir / "frame.png").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  std::string problem;
  EXPECT_FALSE(ReadImageHeader(fifo, &problem));  // returns at once: nothing writes to it
  EXPECT_EQ(problem, "not a regular file: a FIFO, skipped unread");
  EXPECT_TRUE(ReadGuardedImage(fifo, &problem).empty());
  EXPECT_EQ(problem, "not a regular file: a FIFO, skipped unread");
  EXPECT_FALSE(ReadImageHeader(dir.path().string(), &problem));
  EXPECT_EQ(problem, "not a regular file: a folder, skipped unread");
  EXPECT_FALSE(ReadImageHeader((dir / "none.png").string(), &problem));
  EXPECT_EQ(problem, "missing image");
}

// Random bytes behind each format's magic: a header or a reason, never a
// crash. Seeded; the seed is printed when a case fails.
TEST(ImageHeader, RandomHeadersGiveAnAnswerOrAReason) {
  TempDir dir;
  const uint32_t seed = std::random_device{}();
  std::mt19937 rng(seed);
  const std::vector<std::string> magics = {
      std::string("\x89PNG\r\n\x1a\n", 8),    "\xFF\xD8\xFF", std::string("II*\0", 4), std::string("MM\0*", 4), "BM",
      std::string("RIFF\0\0\0\0WEBPVP8X", 16)};
  const std::string path = (dir / "random.img").string();
  for (int i = 0; i < 3000; ++i) {
    std::string bytes = magics[i % magics.size()];
    const size_t n = rng() % 300;
    for (size_t k = 0; k < n; ++k) bytes.push_back(static_cast<char>(rng()));
    testing::WriteBytes(path, bytes);
    std::string problem;
    const auto header = ReadImageHeader(path, &problem);
    if (header) {
      EXPECT_GE(header->width, 0) << "seed " << seed << " case " << i;
      EXPECT_GE(header->height, 0) << "seed " << seed << " case " << i;
    } else {
      EXPECT_FALSE(problem.empty()) << "seed " << seed << " case " << i;
    }
    if (::testing::Test::HasFailure()) break;
  }
}

}  // namespace
}  // namespace seamap
