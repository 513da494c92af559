#include "core/enhance/flat_field.h"

#include <gtest/gtest.h>

#include <thread>

#include "core/util/error.h"
#include "tests/core/enhance/synthetic_images.h"

namespace seamap {
namespace {
using testing::MeanIn;

const cv::Size kSize(240, 180);

// Survey frames: different seabed textures under the same lamp falloff.
std::vector<cv::Mat> Survey(int n, int depth, bool colour, double falloff = 0.6) {
  cv::Mat lamp = testing::RadialFalloff(kSize, falloff);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < n; ++i) {
    cv::Mat scene = colour ? testing::ColorTexture(kSize, 100 + i) : testing::Texture(kSize, 100 + i);
    frames.push_back(testing::ToType(testing::Multiply(scene, lamp), depth));
  }
  return frames;
}

// Corner-to-centre brightness ratio of the mean over many frames (1 = no falloff).
double CornerToCentre(const std::vector<cv::Mat>& frames) {
  cv::Mat sum = cv::Mat::zeros(kSize, CV_32F);
  for (const auto& f : frames) {
    cv::Mat gray = f;
    if (f.channels() == 3) cv::cvtColor(f, gray, cv::COLOR_BGR2GRAY);
    cv::Mat u = testing::ToUnit(gray);
    sum += u;
  }
  const int s = 30;
  double centre = MeanIn(sum, cv::Rect(kSize.width / 2 - s / 2, kSize.height / 2 - s / 2, s, s));
  double corners = (MeanIn(sum, cv::Rect(0, 0, s, s)) + MeanIn(sum, cv::Rect(kSize.width - s, 0, s, s)) +
                    MeanIn(sum, cv::Rect(0, kSize.height - s, s, s)) +
                    MeanIn(sum, cv::Rect(kSize.width - s, kSize.height - s, s, s))) /
                   4;
  return corners / centre;
}

TEST(FlatField, SeededEstimateRemovesRadialFalloff) {
  for (int depth : {CV_8U, CV_16U}) {
    for (bool colour : {false, true}) {
      std::vector<cv::Mat> frames = Survey(30, depth, colour);
      ASSERT_LT(CornerToCentre(frames), 0.6);
      FlatFieldParams p;
      p.learn = false;
      FlatField flat(p);
      flat.Seed(std::vector<cv::Mat>(frames.begin(), frames.begin() + 20));
      std::vector<cv::Mat> corrected;
      for (size_t i = 20; i < frames.size(); ++i) {  // frames the estimate has not seen
        corrected.push_back(flat.Apply(frames[i]));
        ASSERT_EQ(corrected.back().type(), frames[i].type());
      }
      EXPECT_NEAR(CornerToCentre(corrected), 1.0, 0.08) << "depth " << depth << " colour " << colour;
    }
  }
}

TEST(FlatField, CorrectionKeepsOverallBrightness) {
  std::vector<cv::Mat> frames = Survey(10, CV_8U, false);
  FlatField flat;
  flat.Seed(frames);
  cv::Mat out = flat.Correct(frames[0]);
  EXPECT_NEAR(cv::mean(out)[0] / cv::mean(frames[0])[0], 1.0, 0.1);
}

TEST(FlatField, WithoutFramesItPassesThrough) {
  FlatFieldParams p;
  p.learn = false;
  FlatField flat(p);
  cv::Mat img = Survey(1, CV_8U, false)[0];
  EXPECT_EQ(cv::norm(flat.Apply(img), img, cv::NORM_INF), 0);
  EXPECT_EQ(flat.frame_count(), 0);
}

TEST(FlatField, LearnsFromTwoThreadsAtOnce) {
  std::vector<cv::Mat> frames = Survey(16, CV_8U, false);
  FlatField flat;
  auto worker = [&](int start) {
    for (size_t i = start; i < frames.size(); i += 2) flat.Apply(frames[i]);
  };
  std::thread a(worker, 0), b(worker, 1);
  a.join();
  b.join();
  EXPECT_EQ(flat.frame_count(), 16);
  std::vector<cv::Mat> corrected;
  for (const auto& f : frames) corrected.push_back(flat.Correct(f));
  EXPECT_NEAR(CornerToCentre(corrected), 1.0, 0.1);
}

TEST(FlatField, RejectsFramesOfAnotherSize) {
  FlatField flat;
  flat.Add(cv::Mat(40, 60, CV_8UC1, cv::Scalar(10)));
  try {
    flat.Apply(cv::Mat(41, 60, CV_8UC1, cv::Scalar(10)));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("60x40x1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(flat.Add(cv::Mat(40, 60, CV_8UC3)), InputError);
}

TEST(FlatField, ValidatesParametersByName) {
  FlatFieldParams p;
  p.smooth = 0;
  try {
    FlatField f(p);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "flatfield.smooth");
  }
  p = {};
  p.memory = 0;
  EXPECT_THROW(FlatField{p}, InputError);
}

}  // namespace
}  // namespace seamap
