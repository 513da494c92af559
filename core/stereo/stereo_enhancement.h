#pragma once
// Seed 004's enhancement chain in front of the stereo features
// (`stereo-model` and `stereo-locate --feature-enhance off|auto|<chain>`),
// chosen by the rule VO and refinement use (core/enhance/chain_choice.h).
// Here an inlier is a left/right match that the rectified rows, the depth
// range, the ratio test and mutual best all accept: a triangulated point.
#include <vector>

#include "core/enhance/chain_choice.h"
#include "core/stereo/stereo_calibration.h"
#include "core/stereo/stereo_matcher.h"
#include "core/stereo/stereo_pairs.h"

namespace seamap {

// Mean stereo inliers per pair of `pairs` with the features `sift` detects.
EnhancementTrial MeasureStereoInliers(const std::vector<LoadedPair>& pairs, const StereoCalibration& calibration,
                                      const SiftOptions& sift, const StereoMatchOptions& match);

// The chain for `options.spec`; for auto, measured on the first
// options.probe_frames pairs (at least two images: one pair will do).
EnhancementChoice ChooseStereoEnhancement(const FeatureEnhanceOptions& options, const std::vector<LoadedPair>& pairs,
                                          const StereoCalibration& calibration, const SiftOptions& sift,
                                          const StereoMatchOptions& match);

}  // namespace seamap
