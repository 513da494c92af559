#include "core/stereo/stereo_matcher.h"

#include <gtest/gtest.h>

#include <random>

namespace seamap {
namespace {

// 200 keypoints whose right partners carry the same descriptor at (x - disparity, y + row_offset);
// `wrong` of them have their partner at a random place instead (wrong matches on a plain, hazy pair).
void MakePair(double disparity, double row_offset, int wrong, ImageFeatures* left, ImageFeatures* right) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = 200;
  left->descriptors.create(n, 128, CV_8U);
  cv::randu(left->descriptors, 0, 256);
  right->descriptors = left->descriptors.clone();
  left->rect_px.clear();
  right->rect_px.clear();
  left->raw_px.clear();
  for (int k = 0; k < n; ++k) {
    const cv::Point2d p(100 + 1000 * u(rng), 50 + 800 * u(rng));
    left->rect_px.push_back(p);
    left->raw_px.push_back(p);
    right->rect_px.push_back(k < wrong ? cv::Point2d(1200 * u(rng), 900 * u(rng))
                                       : cv::Point2d(p.x - disparity, p.y + row_offset + 0.2 * (u(rng) - 0.5)));
  }
  right->raw_px = right->rect_px;  // size() counts raw keypoints
}

TEST(StereoMatcher, EpipolarCheckTellsAGoodPairFromAnotherRigAndFromSwappedImages) {
  ImageFeatures l, r;
  MakePair(70, 0, 0, &l, &r);
  EXPECT_TRUE(CheckEpipolar(l, r, 0.8).Passes());
  // Most unconstrained matches wrong (plain paint, haze): the ones that agree in row still decide.
  MakePair(70, 0, 120, &l, &r);
  const EpipolarCheck hazy = CheckEpipolar(l, r, 0.8);
  EXPECT_GT(hazy.median_row_px, 2);
  EXPECT_TRUE(hazy.Passes()) << hazy.Describe();
  // Rows 40 px apart: another calibration.
  MakePair(70, 40, 0, &l, &r);
  const EpipolarCheck other = CheckEpipolar(l, r, 0.8);
  EXPECT_FALSE(other.Passes());
  EXPECT_NE(other.Describe().find("not a stereo pair"), std::string::npos) << other.Describe();
  // Negative disparities: left and right swapped.
  MakePair(-70, 0, 0, &l, &r);
  const EpipolarCheck swapped = CheckEpipolar(l, r, 0.8);
  EXPECT_FALSE(swapped.Passes());
  EXPECT_NE(swapped.Describe().find("swapped"), std::string::npos) << swapped.Describe();
}

}  // namespace
}  // namespace seamap
