// Seed 004's chain in front of the stereo features: chosen by the rule VO
// and refinement use, on what the stereo matcher accepts (stereo_enhancement.h).
#include "core/stereo/stereo_enhancement.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

constexpr int kWidth = 400, kHeight = 300, kDisparityPx = 24;

// A rectified rig (no distortion, parallel cameras, 0.25 m baseline).
StereoCalibration ParallelRig() {
  StereoCalibration c;
  c.image_size = {kWidth, kHeight};
  c.K1 = c.K2 = cv::Matx33d(400, 0, 199.5, 0, 400, 149.5, 0, 0, 1);
  c.D1 = c.D2 = std::vector<double>(5, 0.0);
  c.R = cv::Matx33d::eye();
  c.T = cv::Vec3d(-0.25, 0, 0);
  c.Rectify();
  return c;
}

// A blotchy seabed at one range seen through milky water: `contrast` of the
// texture left over a bright veil, sensor noise on top, the right image
// shifted by the disparity.
LoadedPair HazyPair(double contrast, double noise, int seed) {
  cv::Mat1f seabed(kHeight, kWidth + kDisparityPx);
  cv::RNG rng(seed);
  rng.fill(seabed, cv::RNG::UNIFORM, 0, 1);
  cv::GaussianBlur(seabed, seabed, {0, 0}, 1.6);
  cv::normalize(seabed, seabed, 0, 1, cv::NORM_MINMAX);
  const auto view = [&](int x0) {
    cv::Mat1f v = seabed(cv::Rect(x0, 0, kWidth, kHeight)).clone();
    v = 255 * (contrast * v + (1 - contrast) * 0.75);
    cv::Mat1f n(v.size());
    rng.fill(n, cv::RNG::NORMAL, 0, noise);
    cv::Mat out;
    cv::Mat(v + n).convertTo(out, CV_8U);
    return out;
  };
  LoadedPair p;
  p.name = "hazy_" + std::to_string(seed);
  p.left = view(0);  // a point at x in the left image is at x - d in the right
  p.right = view(kDisparityPx);
  return p;
}

TEST(StereoEnhancement, OffAndExplicitChainsNeedNoTrials) {
  const std::vector<LoadedPair> pairs = {HazyPair(0.2, 1, 1)};
  FeatureEnhanceOptions o;
  EXPECT_TRUE(ChooseStereoEnhancement(o, pairs, ParallelRig(), {}, {}).chain.empty());
  o.spec = "clahe:clip_limit=3";
  const EnhancementChoice chosen = ChooseStereoEnhancement(o, pairs, ParallelRig(), {}, {});
  EXPECT_EQ(chosen.chain.Names(), "clahe:clip_limit=3");
  EXPECT_TRUE(chosen.trials.empty());
}

TEST(StereoEnhancement, AutoKeepsAChainThatRaisesTheInliersOnAHazyPair) {
  // Little contrast left under the veil: unenhanced, few keypoints pass SIFT's threshold.
  const std::vector<LoadedPair> pairs = {HazyPair(0.06, 0.6, 2), HazyPair(0.06, 0.6, 3)};
  FeatureEnhanceOptions o;
  o.spec = "auto";
  const EnhancementChoice chosen = ChooseStereoEnhancement(o, pairs, ParallelRig(), {}, {});
  ASSERT_EQ(chosen.trials.size(), 1 + o.candidates.size());
  EXPECT_EQ(chosen.trials[0].chain, "none");
  EXPECT_LT(chosen.trials[0].inliers, o.enough_inliers);
  ASSERT_FALSE(chosen.chain.empty());
  double best = 0;
  for (size_t k = 1; k < chosen.trials.size(); ++k) best = std::max(best, chosen.trials[k].inliers);
  EXPECT_GT(best, chosen.trials[0].inliers * (1 + o.min_gain));
  // What the chosen chain measures is what the locator will get.
  SiftOptions sift;
  sift.enhance = chosen.chain;
  const EnhancementTrial again = MeasureStereoInliers(pairs, ParallelRig(), sift, {});
  EXPECT_NEAR(again.inliers, best, 0.05 * best);
}

TEST(StereoEnhancement, AutoKeepsNoneWhereThePairsMatchWell) {
  const std::vector<LoadedPair> pairs = {HazyPair(0.8, 1, 4)};
  FeatureEnhanceOptions o;
  o.spec = "auto";
  const EnhancementChoice chosen = ChooseStereoEnhancement(o, pairs, ParallelRig(), {}, {});
  ASSERT_EQ(chosen.trials.size(), 1u);  // enough inliers: no chain tried
  EXPECT_GE(chosen.trials[0].inliers, o.enough_inliers);
  EXPECT_TRUE(chosen.chain.empty());
}

TEST(StereoEnhancement, BadSpecNamesTheOption) {
  FeatureEnhanceOptions o;
  o.spec = "sharpen";
  try {
    ChooseStereoEnhancement(o, {HazyPair(0.5, 1, 5)}, ParallelRig(), {}, {});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--feature-enhance"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace seamap
