#include "core/stereo/stereo_enhancement.h"

#include <algorithm>

namespace seamap {

EnhancementTrial MeasureStereoInliers(const std::vector<LoadedPair>& pairs, const StereoCalibration& calibration,
                                      const SiftOptions& sift, const StereoMatchOptions& match) {
  EnhancementTrial trial;
  trial.chain = sift.enhance.Names();
  for (const LoadedPair& p : pairs) {
    ImageFeatures left = DetectSift(p.left, sift), right = DetectSift(p.right, sift);
    left.rect_px = calibration.RectifyLeft(left.raw_px);
    right.rect_px = calibration.RectifyRight(right.raw_px);
    trial.features += 0.5 * static_cast<double>(left.size() + right.size());
    trial.inliers += static_cast<double>(MatchAlongRows(left, right, calibration.rig, match).size());
  }
  if (!pairs.empty()) {
    trial.features /= static_cast<double>(pairs.size());
    trial.inliers /= static_cast<double>(pairs.size());
  }
  return trial;
}

EnhancementChoice ChooseStereoEnhancement(const FeatureEnhanceOptions& options, const std::vector<LoadedPair>& pairs,
                                          const StereoCalibration& calibration, const SiftOptions& sift,
                                          const StereoMatchOptions& match) {
  const size_t probe_pairs = std::min(pairs.size(), static_cast<size_t>(std::max(1, options.probe_frames / 2)));
  const std::vector<LoadedPair> probe(pairs.begin(), pairs.begin() + static_cast<long>(probe_pairs));
  std::vector<cv::Mat> seed;  // the flat field learns from both cameras
  for (const LoadedPair& p : probe) seed.insert(seed.end(), {p.left, p.right});
  return ChooseEnhancementByInliers(options, seed, [&](const EnhanceChain& chain) {
    SiftOptions tried = sift;
    tried.enhance = chain;
    return MeasureStereoInliers(probe, calibration, tried, match);
  });
}

}  // namespace seamap
