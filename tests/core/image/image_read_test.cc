#include "core/image/image_read.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "tests/testing/hostile_png.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

TEST(ReadGuardedImage, DecodesUnchanged) {
  TempDir dir;
  const std::string path = (dir / "frame.png").string();
  cv::Mat sixteen(30, 40, CV_16UC3, cv::Scalar(1000, 2000, 3000));
  ASSERT_TRUE(cv::imwrite(path, sixteen));
  std::string problem;
  const cv::Mat read = ReadGuardedImage(path, &problem);
  ASSERT_FALSE(read.empty()) << problem;
  EXPECT_EQ(read.type(), CV_16UC3);
  EXPECT_EQ(cv::norm(read, sixteen, cv::NORM_INF), 0);
}

TEST(ReadGuardedImage, RefusesWhatItShouldNotDecodeWithTheReason) {
  TempDir dir;
  std::string problem;
  EXPECT_TRUE(ReadGuardedImage((dir / "none.png").string(), &problem).empty());
  EXPECT_EQ(problem, "missing image");

  // A 2 KB header that claims 30000 x 30000 pixels.
  const std::string claiming = (dir / "claims.png").string();
  testing::WriteBytes(claiming, testing::ClaimingPng(30000, 30000));
  EXPECT_TRUE(ReadGuardedImage(claiming, &problem).empty());
  EXPECT_EQ(problem.rfind("image too large", 0), 0u) << problem;

  // A real image over a lower limit.
  const std::string small = (dir / "small.png").string();
  ASSERT_TRUE(cv::imwrite(small, cv::Mat(100, 100, CV_8UC1, cv::Scalar(7))));
  EXPECT_TRUE(ReadGuardedImage(small, &problem, 5000).empty());
  EXPECT_EQ(problem.rfind("image too large", 0), 0u) << problem;
  EXPECT_FALSE(ReadGuardedImage(small, &problem, 10000).empty()) << problem;

  const std::string text = (dir / "text.png").string();
  testing::WriteBytes(text, "not an image");
  EXPECT_TRUE(ReadGuardedImage(text, &problem).empty());
  EXPECT_EQ(problem, "unreadable image");
}

}  // namespace
}  // namespace seamap
