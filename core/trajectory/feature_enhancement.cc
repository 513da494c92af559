#include "core/trajectory/feature_enhancement.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>

#include "core/util/error.h"

namespace seamap {

void FeatureEnhanceOptions::Check() const {
  if (spec.empty()) throw InputError("", 0, "--feature-enhance", "expected off, auto or an op list");
  if (spec != "off" && spec != "auto") EnhanceChain::FromOpList(spec, "--feature-enhance");  // throws naming the op
  if (probe_frames < 2) throw InputError("", 0, "--feature-enhance", "auto needs at least two probe frames");
  if (!(min_gain >= 0) || !(enough_inliers > 0))
    throw InputError("", 0, "--feature-enhance", "auto needs a gain >= 0 and an inlier level > 0");
}

EnhancementTrial MeasureInliers(const std::vector<cv::Mat>& frames, const CameraModel& camera,
                                const FeatureOptions& options) {
  EnhancementTrial trial;
  trial.chain = options.enhance.Names();
  std::vector<FrameFeatures> features;
  for (const cv::Mat& f : frames) {
    features.push_back(DetectFeatures(f, camera, options));
    trial.features += static_cast<double>(features.back().ideal_px.size());
  }
  if (!frames.empty()) trial.features /= static_cast<double>(frames.size());
  int pairs = 0;
  for (size_t i = 1; i < features.size(); ++i, ++pairs) {
    const FrameFeatures &a = features[i - 1], &b = features[i];
    if (a.ideal_px.size() < 2 || b.ideal_px.size() < 2) continue;
    cv::Mat da, db;
    a.descriptors.convertTo(da, CV_32F);
    b.descriptors.convertTo(db, CV_32F);
    std::vector<std::vector<cv::DMatch>> knn;
    cv::BFMatcher(cv::NORM_L2).knnMatch(db, da, knn, 2);
    std::vector<cv::Point2d> p1, p2;
    for (const auto& m : knn)
      if (m.size() == 2 && m[0].distance < 0.7 * m[1].distance) {
        p1.push_back(a.ideal_px[m[0].trainIdx]);
        p2.push_back(b.ideal_px[m[0].queryIdx]);
      }
    if (p1.size() < 8) continue;
    cv::Mat mask;
    const cv::Mat e = cv::findEssentialMat(p1, p2, cv::Mat(camera.K()), cv::USAC_MAGSAC, 0.999, 1.0, mask);
    if (!e.empty()) trial.inliers += cv::countNonZero(mask);
  }
  if (pairs > 0) trial.inliers /= pairs;
  return trial;
}

EnhancementChoice ChooseFeatureEnhancement(const FeatureEnhanceOptions& options, const std::vector<cv::Mat>& probe,
                                           const CameraModel& camera, const FeatureOptions& features) {
  options.Check();
  EnhancementChoice choice;
  if (options.spec == "off") return choice;
  if (options.spec != "auto") {
    choice.chain = EnhanceChain::FromOpList(options.spec, "--feature-enhance");
    if (choice.chain.SeedFrames() > 0) choice.chain.Seed(probe);
    return choice;
  }
  if (probe.size() < 2) return choice;
  FeatureOptions tried = features;
  tried.enhance = EnhanceChain();
  choice.trials.push_back(MeasureInliers(probe, camera, tried));
  if (choice.trials.front().inliers >= options.enough_inliers) return choice;
  double best = choice.trials.front().inliers * (1 + options.min_gain);
  for (const std::string& list : options.candidates) {
    EnhanceChain chain = EnhanceChain::FromOpList(list, "--feature-enhance");
    if (chain.SeedFrames() > 0) chain.Seed(probe);
    tried.enhance = chain;
    choice.trials.push_back(MeasureInliers(probe, camera, tried));
    if (choice.trials.back().inliers > best) {
      best = choice.trials.back().inliers;
      // A fresh copy for the survey: the probe's frames taught the flat
      // field once already (Seed), not twice.
      choice.chain = EnhanceChain::FromOpList(list, "--feature-enhance");
      if (choice.chain.SeedFrames() > 0) choice.chain.Seed(probe);
    }
  }
  return choice;
}

}  // namespace seamap
