#include "core/enhance/color_balance.h"

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/core/enhance/synthetic_images.h"

namespace seamap {
namespace {

// Linear-light scene -> gamma-2.2 encoded 8-bit with a blue-green cast applied in linear light.
cv::Mat WithCast(const cv::Mat& linear, const cv::Scalar& cast, int depth) {
  cv::Mat c;
  cv::multiply(linear, cast, c);
  cv::pow(c, 1.0 / 2.2, c);
  return testing::ToType(c, depth);
}

cv::Scalar LinearMeans(const cv::Mat& encoded) {
  cv::Mat lin;
  cv::pow(testing::ToUnit(encoded), 2.2, lin);
  return cv::mean(lin);
}

TEST(ColorBalance, RemovesKnownCastInLinearLight) {
  cv::Mat gray = testing::Texture({240, 180}, 13, 0.05, 0.8);
  cv::Mat linear;
  cv::merge(std::vector<cv::Mat>{gray, gray, gray}, linear);
  for (int depth : {CV_8U, CV_16U}) {
    cv::Mat img = WithCast(linear, cv::Scalar(1.0, 0.8, 0.35), depth);
    cv::Scalar before = LinearMeans(img);
    ASSERT_LT(before[2] / before[0], 0.4);
    cv::Mat out = BalanceColor(img, {});
    ASSERT_EQ(out.type(), img.type());
    cv::Scalar after = LinearMeans(out);
    EXPECT_NEAR(after[2] / after[0], 1.0, 0.03) << "depth " << depth;
    EXPECT_NEAR(after[1] / after[0], 1.0, 0.03) << "depth " << depth;
  }
}

TEST(ColorBalance, GainsAreCappedAndGrayIsUntouched) {
  cv::Mat img(20, 20, CV_8UC3, cv::Scalar(200, 200, 2));
  ColorBalanceParams p;
  p.max_gain = 2.0;
  cv::Vec3d g = GrayWorldGains(img, p);
  EXPECT_DOUBLE_EQ(g[2], 2.0);
  cv::Mat gray(20, 20, CV_16UC1, cv::Scalar(1234));
  EXPECT_EQ(cv::norm(BalanceColor(gray, {}), gray, cv::NORM_INF), 0);
}

TEST(ColorBalance, ValidatesParametersByName) {
  ColorBalanceParams p;
  p.max_gain = 0.1;
  try {
    BalanceColor(cv::Mat(4, 4, CV_8UC3), p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "colorbalance.max_gain");
  }
  EXPECT_THROW(BalanceColor(cv::Mat(4, 4, CV_8UC4), {}), InputError);
}

}  // namespace
}  // namespace seamap
