#include <gtest/gtest.h>

#include "core/enhance/clahe.h"
#include "core/enhance/gamma.h"
#include "core/util/error.h"
#include "tests/core/enhance/synthetic_images.h"

namespace seamap {
namespace {
using testing::ToType;

TEST(Gamma, FollowsSeedFormulaAndKeepsEndpoints) {
  cv::Mat ramp(1, 256, CV_8UC1);
  for (int i = 0; i < 256; ++i) ramp.at<uchar>(i) = static_cast<uchar>(i);
  cv::Mat out = ApplyGamma(ramp, {0.5});
  EXPECT_EQ(out.at<uchar>(0), 0);
  EXPECT_EQ(out.at<uchar>(255), 255);
  EXPECT_EQ(out.at<uchar>(64), cvRound(255 * std::sqrt(64 / 255.0)));
  for (int i = 1; i < 256; ++i) EXPECT_GE(out.at<uchar>(i), out.at<uchar>(i - 1));
  EXPECT_EQ(cv::norm(ApplyGamma(ramp, {1.0}), ramp, cv::NORM_INF), 0);
}

TEST(Gamma, Works16BitColour) {
  cv::Mat img(3, 3, CV_16UC3, cv::Scalar(16384, 32768, 65535));
  cv::Mat out = ApplyGamma(img, {2.0});
  ASSERT_EQ(out.type(), CV_16UC3);
  EXPECT_NEAR(out.at<cv::Vec3w>(1, 1)[0], 65535.0 * std::pow(16384 / 65535.0, 2), 1.0);
  EXPECT_EQ(out.at<cv::Vec3w>(1, 1)[2], 65535);
}

TEST(Gamma, RejectsNonPositiveGammaNamingIt) {
  try {
    ApplyGamma(cv::Mat(2, 2, CV_8UC1), {0.0});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "gamma.gamma");
  }
}

TEST(Clahe, RaisesContrastOfFlatLowContrastImage) {
  // Smooth low-contrast relief (no pebbles: they would dominate the histogram).
  cv::Mat coarse(24, 32, CV_32F), unit;
  cv::randu(coarse, 0.45, 0.55);
  cv::resize(coarse, unit, cv::Size(256, 192), 0, 0, cv::INTER_CUBIC);
  for (int depth : {CV_8U, CV_16U}) {
    cv::Mat img = ToType(unit, depth);
    cv::Mat out = ApplyClahe(img, {2.0, 8});
    ASSERT_EQ(out.type(), img.type());
    cv::Scalar m0, s0, m1, s1;
    cv::meanStdDev(testing::ToUnit(img), m0, s0);
    cv::meanStdDev(testing::ToUnit(out), m1, s1);
    EXPECT_GT(s1[0], 2.0 * s0[0]) << "depth " << depth;
  }
}

TEST(Clahe, ColourKeepsChromaAndEqualisesLuma) {
  cv::Mat unit = testing::ColorTexture({200, 160}, 2);
  unit = unit * 0.2 + 0.3;  // dim, low contrast
  cv::Mat img = ToType(unit, CV_8U);
  cv::Mat out = ApplyClahe(img, {3.0, 4});
  ASSERT_EQ(out.type(), CV_8UC3);
  cv::Mat y0, y1;
  cv::cvtColor(img, y0, cv::COLOR_BGR2YCrCb);
  cv::cvtColor(out, y1, cv::COLOR_BGR2YCrCb);
  cv::Scalar c0 = cv::mean(y0), c1 = cv::mean(y1);
  EXPECT_NEAR(c0[1], c1[1], 3.0);  // Cr
  EXPECT_NEAR(c0[2], c1[2], 3.0);  // Cb
  cv::Scalar m0, s0, m1, s1;
  std::vector<cv::Mat> p0, p1;
  cv::split(y0, p0);
  cv::split(y1, p1);
  cv::meanStdDev(p0[0], m0, s0);
  cv::meanStdDev(p1[0], m1, s1);
  EXPECT_GT(s1[0], 1.5 * s0[0]);
}

TEST(Clahe, ValidatesParametersByName) {
  cv::Mat img(8, 8, CV_8UC1, cv::Scalar(3));
  try {
    ApplyClahe(img, {-1.0, 8});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "clahe.clip_limit");
  }
  try {
    ApplyClahe(img, {2.0, 0});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "clahe.tile_grid");
  }
  EXPECT_THROW(ApplyClahe(cv::Mat(8, 8, CV_32FC1), {}), InputError);
}

}  // namespace
}  // namespace seamap
