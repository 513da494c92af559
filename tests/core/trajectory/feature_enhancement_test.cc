#include "core/trajectory/feature_enhancement.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

CameraModel SmallCamera() {
  CameraModel c;
  c.width = 320;
  c.height = 240;
  c.fx = c.fy = 300;
  c.cx = 159.5;
  c.cy = 119.5;
  return c;
}

// A blotchy seabed seen through milky water: frames shifted 8 px apart.
std::vector<cv::Mat> HazyFrames(double contrast, int count) {
  cv::Mat seabed(240, 480, CV_8U);
  cv::RNG rng(3);
  rng.fill(seabed, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(seabed, seabed, {0, 0}, 2.0);
  cv::normalize(seabed, seabed, 0, 255, cv::NORM_MINMAX);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < count; ++i) {
    cv::Mat f = seabed(cv::Rect(8 * i, 0, 320, 240)).clone();
    f.convertTo(f, CV_8U, contrast, 200 * (1 - contrast));
    frames.push_back(f);
  }
  return frames;
}

TEST(FeatureEnhancement, OffAndExplicitChainsNeedNoTrials) {
  FeatureEnhanceOptions o;
  const auto frames = HazyFrames(0.5, 3);
  EXPECT_TRUE(ChooseFeatureEnhancement(o, frames, SmallCamera(), {}).chain.empty());
  o.spec = "clahe:clip_limit=3";
  const EnhancementChoice chosen = ChooseFeatureEnhancement(o, frames, SmallCamera(), {});
  EXPECT_EQ(chosen.chain.Names(), "clahe:clip_limit=3");
  EXPECT_TRUE(chosen.trials.empty());
}

TEST(FeatureEnhancement, AutoKeepsNoneWhereTheFramesMatchWell) {
  // Plenty of inliers unenhanced: none is kept, no chain is tried.
  FeatureEnhanceOptions o;
  o.spec = "auto";
  o.enough_inliers = 20;
  const EnhancementChoice chosen = ChooseFeatureEnhancement(o, HazyFrames(0.6, 4), SmallCamera(), {});
  ASSERT_EQ(chosen.trials.size(), 1u);
  EXPECT_EQ(chosen.trials[0].chain, "none");
  EXPECT_GT(chosen.trials[0].inliers, 20);
  EXPECT_TRUE(chosen.chain.empty());
  // Asked to try them all, it keeps only a chain that beats none by the margin.
  o.enough_inliers = 1e9;
  const EnhancementChoice all = ChooseFeatureEnhancement(o, HazyFrames(0.6, 4), SmallCamera(), {});
  ASSERT_EQ(all.trials.size(), 1 + o.candidates.size());
  double best = 0;
  for (size_t k = 1; k < all.trials.size(); ++k) best = std::max(best, all.trials[k].inliers);
  if (best > all.trials[0].inliers * (1 + o.min_gain))
    EXPECT_FALSE(all.chain.empty());
  else
    EXPECT_TRUE(all.chain.empty());
}

TEST(FeatureEnhancement, BadSpecsNameTheOption) {
  FeatureEnhanceOptions o;
  o.spec = "";
  EXPECT_THROW(o.Check(), InputError);
  o.spec = "sharpen";
  EXPECT_THROW(o.Check(), InputError);
  o.spec = "auto";
  o.probe_frames = 1;
  try {
    o.Check();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--feature-enhance");
  }
}

}  // namespace
}  // namespace seamap
