#include "core/enhance/dehaze.h"

#include <gtest/gtest.h>

#include "core/enhance/blur_metric.h"
#include "core/enhance/guided_filter.h"
#include "core/util/error.h"
#include "tests/core/enhance/synthetic_images.h"

namespace seamap {
namespace {
using testing::ToType;
using testing::ToUnit;

// Transmission falling from 0.7 (top) to 0.4 (bottom), like haze thickening with range.
cv::Mat KnownTransmission(cv::Size size) {
  cv::Mat t(size, CV_32F);
  for (int y = 0; y < size.height; ++y) t.row(y).setTo(0.7 - 0.3 * y / (size.height - 1));
  return t;
}

// I = J t + A (1 - t)  (eq. 20), per channel.
cv::Mat Haze(const cv::Mat& clear, const cv::Mat& t, const cv::Scalar& a) {
  cv::Mat one_minus = 1.0 - t;
  cv::Mat veil(clear.size(), clear.type(), a);
  return testing::Multiply(clear, t) + testing::Multiply(veil, one_minus);
}

double RmsContrast(const cv::Mat& unit) {
  cv::Mat gray = unit;
  if (unit.channels() == 3) cv::cvtColor(unit, gray, cv::COLOR_BGR2GRAY);
  cv::Scalar m, s;
  cv::meanStdDev(gray, m, s);
  return s[0];
}

DehazeParams Always() {
  DehazeParams p;
  p.gate = false;
  return p;
}

TEST(Dehaze, RecoversSceneAndContrastOfKnownGrayHaze) {
  cv::Mat clear = testing::Texture({320, 240}, 7, 0.0, 0.9);
  cv::Mat t = KnownTransmission(clear.size());
  cv::Mat hazy = Haze(clear, t, cv::Scalar(0.85));
  for (int depth : {CV_8U, CV_16U}) {
    cv::Mat img = ToType(hazy, depth);
    bool applied = false;
    cv::Mat out = Dehaze(img, Always(), &applied);
    ASSERT_TRUE(applied);
    ASSERT_EQ(out.type(), img.type());
    cv::Mat j = ToUnit(out);
    EXPECT_GT(RmsContrast(j), 1.5 * RmsContrast(ToUnit(img)));
    // Much closer to the clear scene than the hazy input was.
    double err_in = cv::mean(cv::abs(ToUnit(img) - clear))[0];
    double err_out = cv::mean(cv::abs(j - clear))[0];
    EXPECT_LT(err_out, 0.35 * err_in) << "in " << err_in << " out " << err_out;
  }
}

TEST(Dehaze, EstimatesAirlightAndTransmission) {
  cv::Mat clear = testing::Texture({320, 240}, 8, 0.0, 0.9);
  cv::Mat t = KnownTransmission(clear.size());
  cv::Mat img = ToType(Haze(clear, t, cv::Scalar(0.85)), CV_8U);
  DehazeParams p = Always();
  p.omega = 1.0;
  cv::Scalar a = EstimateAirlight(img, DarkChannel(img, p.window), p.airlight_fraction);
  EXPECT_NEAR(a[0], 0.85, 0.12);
  cv::Mat est = EstimateTransmission(img, ToUnit(img), a, p);
  EXPECT_LT(cv::mean(cv::abs(est - t))[0], 0.08);
}

TEST(Dehaze, ColourUsesBlueGreenDarkChannelDespiteAbsentRed) {
  cv::Mat clear = testing::ColorTexture({320, 240}, 9);
  std::vector<cv::Mat> planes;
  cv::split(clear, planes);
  planes[0] -= 0.05;  // let the darkest blue/green reach 0, as the prior expects
  planes[1] -= 0.05;
  planes[2] = planes[2] * 0.1 + 0.6;  // red absorbed: no dark red pixels anywhere
  cv::merge(planes, clear);
  cv::max(clear, 0.0, clear);
  cv::Mat t = KnownTransmission(clear.size());
  cv::Mat img = ToType(Haze(clear, t, cv::Scalar(0.8, 0.75, 0.3)), CV_8U);
  cv::Mat out = Dehaze(img, Always());
  ASSERT_EQ(out.type(), CV_8UC3);
  EXPECT_GT(RmsContrast(ToUnit(out)), 1.4 * RmsContrast(ToUnit(img)));
  EXPECT_LT(cv::mean(cv::abs(ToUnit(out) - clear))[0], 0.5 * cv::mean(cv::abs(ToUnit(img) - clear))[0]);
}

TEST(Dehaze, TransmissionFloorBoundsAmplification) {
  // Pure veil: t would be ~0, so the floor decides the gain.
  cv::Mat img(64, 64, CV_8UC1, cv::Scalar(200));
  img(cv::Rect(0, 0, 32, 64)).setTo(190);
  DehazeParams p = Always();
  p.t0 = 0.5;
  cv::Mat out = Dehaze(img, p);
  double lo, hi;
  cv::minMaxLoc(out, &lo, &hi);
  EXPECT_LE(hi - lo, 2.0 * 10 + 2);  // 1 / t0 = 2x the 10-level step at most
}

TEST(Dehaze, GateSkipsSharpClearFramesAndTakesHazyOnes) {
  cv::Mat clear = testing::Texture({320, 240}, 10, 0.0, 1.0);
  cv::Mat hazy = Haze(clear, cv::Mat(clear.size(), CV_32F, cv::Scalar(0.3)), cv::Scalar(0.8));
  cv::GaussianBlur(hazy, hazy, cv::Size(), 1.5);
  cv::Mat sharp8 = ToType(clear, CV_8U), hazy8 = ToType(hazy, CV_8U);
  const double v_sharp = LaplacianVariance(sharp8, 1), v_hazy = LaplacianVariance(hazy8, 1);
  ASSERT_LT(v_hazy, 0.2 * v_sharp);

  DehazeParams p;  // gate on, threshold between the two frames
  p.blur_threshold = std::sqrt(v_sharp * v_hazy);
  bool applied = true;
  cv::Mat out = Dehaze(sharp8, p, &applied);
  EXPECT_FALSE(applied);
  EXPECT_EQ(cv::norm(out, sharp8, cv::NORM_INF), 0);
  out = Dehaze(hazy8, p, &applied);
  EXPECT_TRUE(applied);
  EXPECT_GT(cv::norm(out, hazy8, cv::NORM_INF), 0);
}

TEST(Dehaze, ValidatesParametersByName) {
  cv::Mat img(32, 32, CV_8UC3, cv::Scalar::all(50));
  auto field_of = [&](DehazeParams p) {
    try {
      Dehaze(img, p);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string("no error");
  };
  DehazeParams p;
  p.t0 = 0;
  EXPECT_EQ(field_of(p), "dehaze.t0");
  p = {};
  p.omega = 1.5;
  EXPECT_EQ(field_of(p), "dehaze.omega");
  p = {};
  p.window = 0;
  EXPECT_EQ(field_of(p), "dehaze.window");
  p = {};
  p.guided_eps = 0;
  EXPECT_EQ(field_of(p), "dehaze.guided_eps");
  EXPECT_EQ(field_of(DehazeParams{}), "no error");
}

TEST(BlurMetric, DropsWithBlurAndMatchesAcrossBitDepths) {
  cv::Mat unit = testing::Texture({256, 192}, 11);
  cv::Mat blurred;
  cv::GaussianBlur(unit, blurred, cv::Size(), 2.0);
  EXPECT_LT(LaplacianVariance(ToType(blurred, CV_8U)), 0.3 * LaplacianVariance(ToType(unit, CV_8U)));
  EXPECT_NEAR(LaplacianVariance(ToType(unit, CV_16U)) / LaplacianVariance(ToType(unit, CV_8U)), 1.0, 0.05);
}

TEST(BlurMetric, OneLevelDownIgnoresSensorNoise) {
  cv::Mat unit = testing::Texture({256, 192}, 12);
  cv::Mat hazy = unit * 0.4 + 0.5, noise(unit.size(), CV_32F);
  cv::randn(noise, 0.0, 0.02);
  hazy += noise;
  // One level down, noise no longer hides that the hazy frame has less contrast.
  EXPECT_LT(LaplacianVariance(ToType(hazy, CV_8U), 1), 0.5 * LaplacianVariance(ToType(unit, CV_8U), 1));
}

TEST(GuidedFilter, SmoothsNoiseButKeepsGuideEdges) {
  cv::Mat guide(100, 100, CV_32F, cv::Scalar(0.2));
  guide(cv::Rect(50, 0, 50, 100)).setTo(0.8);
  cv::Mat noisy = guide.clone(), noise(guide.size(), CV_32F);
  cv::randn(noise, 0, 0.05);
  noisy += noise;
  for (int sub : {1, 2}) {
    cv::Mat out = GuidedFilter(guide, noisy, 8, 1e-3, sub);
    EXPECT_LT(cv::mean(cv::abs(out - guide))[0], 0.5 * cv::mean(cv::abs(noisy - guide))[0]) << sub;
    EXPECT_GT(cv::mean(out(cv::Rect(52, 0, 10, 100)))[0] - cv::mean(out(cv::Rect(38, 0, 10, 100)))[0], 0.5);
  }
}

}  // namespace
}  // namespace seamap
