#include "core/trajectory/feature_enhancement.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>

namespace seamap {

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
  return ChooseEnhancementByInliers(options, probe, [&](const EnhanceChain& chain) {
    FeatureOptions tried = features;
    tried.enhance = chain;
    return MeasureInliers(probe, camera, tried);
  });
}

}  // namespace seamap
