#pragma once
// Seed 004's enhancement chain in front of the registration features (VO,
// refine): `--feature-enhance off|auto|<chain>` (core/enhance/chain_choice.h
// holds the rule). Here an inlier is a match between consecutive frames that
// one essential matrix explains (what the motion is estimated from).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/enhance/chain_choice.h"
#include "core/trajectory/frame_features.h"

namespace seamap {

// Mean essential-matrix inliers per consecutive pair of `frames` (Lowe 0.7,
// five-point RANSAC at 1 px) with the features `options` detect.
EnhancementTrial MeasureInliers(const std::vector<cv::Mat>& frames, const CameraModel& camera,
                                const FeatureOptions& options);

// The chain for `options.spec`; for auto, `probe` holds the first frames
// (at least two; fewer: none).
EnhancementChoice ChooseFeatureEnhancement(const FeatureEnhanceOptions& options, const std::vector<cv::Mat>& probe,
                                           const CameraModel& camera, const FeatureOptions& features);

}  // namespace seamap
