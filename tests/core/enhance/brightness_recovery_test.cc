#include "core/enhance/brightness_recovery.h"

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/core/enhance/synthetic_images.h"

namespace seamap {
namespace {
using testing::MeanIn;

// Texture under an illumination ramp from `dark` (left) to 1 (right).
cv::Mat LitByRamp(const cv::Mat& texture, double dark) {
  cv::Mat ramp(texture.size(), CV_32F);
  for (int x = 0; x < texture.cols; ++x) ramp.col(x).setTo(dark + (1.0 - dark) * x / (texture.cols - 1));
  return testing::Multiply(texture, ramp);
}

// Ratio of the darkest to the brightest mean over vertical strips, 1 = even lighting.
double StripEvenness(const cv::Mat& unit) {
  cv::Mat gray = unit;
  if (unit.channels() == 3) cv::cvtColor(unit, gray, cv::COLOR_BGR2GRAY);
  double lo = 1e9, hi = 0;
  const int strips = 6, w = gray.cols / strips;
  for (int i = 0; i < strips; ++i) {
    double m = MeanIn(gray, cv::Rect(i * w, 0, w, gray.rows));
    lo = std::min(lo, m);
    hi = std::max(hi, m);
  }
  return lo / hi;
}

TEST(BrightnessRecovery, EqualisesWindowMeansUnderIlluminationGradient) {
  cv::Mat lit = LitByRamp(testing::Texture({320, 240}, 3), 0.25);
  for (int depth : {CV_8U, CV_16U}) {
    cv::Mat img = testing::ToType(lit, depth);
    ASSERT_LT(StripEvenness(testing::ToUnit(img)), 0.45);
    cv::Mat out = RecoverBrightness(img, {});
    ASSERT_EQ(out.type(), img.type());
    EXPECT_GT(StripEvenness(testing::ToUnit(out)), 0.85)
        << "depth " << depth << " texture alone " << StripEvenness(testing::Texture({320, 240}, 3));
  }
}

TEST(BrightnessRecovery, EqualisesLocalContrastToo) {
  cv::Mat unit =
      testing::ToUnit(RecoverBrightness(testing::ToType(LitByRamp(testing::Texture({320, 240}, 4), 0.3), CV_8U), {}));
  cv::Scalar m, s_left, s_right;
  cv::meanStdDev(unit(cv::Rect(0, 0, 80, 240)), m, s_left);
  cv::meanStdDev(unit(cv::Rect(240, 0, 80, 240)), m, s_right);
  EXPECT_NEAR(s_left[0] / s_right[0], 1.0, 0.2);
}

TEST(BrightnessRecovery, ColourKeepsHueWhileEvening) {
  cv::Mat lit = LitByRamp(testing::ColorTexture({320, 240}, 5), 0.3);
  cv::Mat img = testing::ToType(lit, CV_8U);
  cv::Mat out = RecoverBrightness(img, {});
  ASSERT_EQ(out.type(), CV_8UC3);
  EXPECT_GT(StripEvenness(testing::ToUnit(out)), 0.8);
  cv::Mat y0, y1;
  cv::cvtColor(img, y0, cv::COLOR_BGR2YCrCb);
  cv::cvtColor(out, y1, cv::COLOR_BGR2YCrCb);
  EXPECT_NEAR(cv::mean(y0)[1], cv::mean(y1)[1], 3.0);
  EXPECT_NEAR(cv::mean(y0)[2], cv::mean(y1)[2], 3.0);
}

TEST(BrightnessRecovery, StrengthZeroIsIdentity) {
  cv::Mat img = testing::ToType(testing::Texture({64, 48}, 6), CV_8U);
  BrightnessParams p;
  p.strength = 0.0;
  EXPECT_LE(cv::norm(RecoverBrightness(img, p), img, cv::NORM_INF), 1.0);
}

TEST(BrightnessRecovery, BlackFrameStaysBlack) {
  cv::Mat black(48, 64, CV_16UC1, cv::Scalar(0));
  EXPECT_EQ(cv::countNonZero(RecoverBrightness(black, {})), 0);
}

TEST(BrightnessRecovery, ValidatesParametersByName) {
  cv::Mat img(32, 32, CV_8UC1, cv::Scalar(9));
  auto field_of = [&](BrightnessParams p) {
    try {
      RecoverBrightness(img, p);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("no error");
  };
  BrightnessParams p;
  p.window = 1;
  EXPECT_EQ(field_of(p), "brightness.window");
  p = {};
  p.max_gain = 0.5;
  EXPECT_EQ(field_of(p), "brightness.max_gain");
  p = {};
  p.percentile = 0;
  EXPECT_EQ(field_of(p), "brightness.percentile");
  p = {};
  p.strength = 2;
  EXPECT_EQ(field_of(p), "brightness.strength");
}

}  // namespace
}  // namespace seamap
