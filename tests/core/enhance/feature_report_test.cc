#include "core/enhance/feature_report.h"

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/core/enhance/synthetic_images.h"

namespace seamap {
namespace {

// Overlapping crops of one seabed, as consecutive survey frames.
std::vector<cv::Mat> Sequence(double contrast) {
  cv::Mat world = testing::Texture({520, 200}, 50, 0.5 - contrast / 2, 0.5 + contrast / 2);
  std::vector<cv::Mat> frames;
  for (int i = 0; i < 4; ++i) frames.push_back(testing::ToType(world(cv::Rect(40 * i, 20, 240, 160)), CV_8U));
  return frames;
}

TEST(FeatureReport, CountsFeaturesAndGeometricMatches) {
  for (FeatureDetector d : {FeatureDetector::kSift, FeatureDetector::kOrb}) {
    FeatureStats s = MeasureFeatures(Sequence(0.9), d);
    EXPECT_EQ(s.frames, 4);
    EXPECT_GT(s.features, 20);
    EXPECT_GT(s.matches, 10);
    EXPECT_GT(s.inliers, 0.5 * s.matches);  // pure translation: most cross-checked matches fit
    EXPECT_LE(s.inliers, s.matches);
  }
}

TEST(FeatureReport, EnhancementOfFaintFramesRaisesMatches) {
  std::vector<cv::Mat> faint = Sequence(0.15);
  ChainReport r = ReportChain(EnhanceChain::FromOpList("clahe:clip_limit=4", "test"), faint, FeatureDetector::kSift);
  EXPECT_EQ(r.chain, "clahe:clip_limit=4");
  EXPECT_GT(r.after.features, r.before.features);
  EXPECT_GT(r.after.inliers, r.before.inliers) << r.before.features << " -> " << r.after.features;
  std::string table = FormatReportTable({r}, "sift");
  EXPECT_NE(table.find("clahe:clip_limit=4"), std::string::npos);
  EXPECT_NE(table.find("inliers/pair"), std::string::npos);
}

TEST(FeatureReport, IdentityChainChangesNothing) {
  std::vector<cv::Mat> frames = Sequence(0.5);
  FeatureStats before = MeasureFeatures(frames, FeatureDetector::kOrb);
  ChainReport r = ReportChain(EnhanceChain(), frames, FeatureDetector::kOrb, &before);
  EXPECT_EQ(r.after.features, r.before.features);
  EXPECT_EQ(r.after.matches, r.before.matches);
}

TEST(FeatureReport, DetectorNameIsValidated) {
  EXPECT_EQ(ParseFeatureDetector("orb", "--detector"), FeatureDetector::kOrb);
  try {
    ParseFeatureDetector("surf", "--detector");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--detector");
  }
}

}  // namespace
}  // namespace seamap
