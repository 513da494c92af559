#pragma once
// Seed 004's enhancement chain in front of the registration features (VO,
// refine): `--feature-enhance off|auto|<chain>`. `auto` measures, on the
// survey's first frames, how many matches between consecutive frames one
// essential matrix explains (the inliers the motion is estimated from) with
// each candidate chain, and keeps the best only where the frames are short
// of inliers and it beats no enhancement clearly: on frames that match well
// the chain costs time and accuracy (docs/TERRAIN.md measures both).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/enhance/enhance_chain.h"
#include "core/trajectory/frame_features.h"

namespace seamap {

struct FeatureEnhanceOptions {
  std::string spec = "off";  // off | auto | an op list (seamap enhance --ops)
  int probe_frames = 8;      // auto: the first frames it tries the chains on
  double min_gain = 0.1;     // auto: keep a chain only with this many more inliers (share)
  // auto: with this many inliers per pair unenhanced, none is kept without
  // trying chains: more matches from enhanced (noisier) pixels then do not
  // make the motion better (docs/TERRAIN.md: drift 0.83 -> 1.16 % with
  // dehazing that raised the inliers from 573 to 788).
  double enough_inliers = 200;
  // auto: the chains tried, each against none.
  std::vector<std::string> candidates = {"dehaze:gate=false", "colorbalance,dehaze:gate=false",
                                         "flatfield,dehaze:gate=false", "default"};
  void Check() const;  // InputError naming --feature-enhance
};

struct EnhancementTrial {
  std::string chain;    // EnhanceChain::Names()
  double inliers = 0;   // mean per consecutive pair
  double features = 0;  // mean per frame
};

struct EnhancementChoice {
  EnhanceChain chain;                    // empty: none
  std::vector<EnhancementTrial> trials;  // auto: none first, then each candidate
};

// Mean essential-matrix inliers per consecutive pair of `frames` (Lowe 0.7,
// five-point RANSAC at 1 px) with the features `options` detect.
EnhancementTrial MeasureInliers(const std::vector<cv::Mat>& frames, const CameraModel& camera,
                                const FeatureOptions& options);

// The chain for `options.spec`; for auto, `probe` holds the first frames
// (at least two; fewer: none).
EnhancementChoice ChooseFeatureEnhancement(const FeatureEnhanceOptions& options, const std::vector<cv::Mat>& probe,
                                           const CameraModel& camera, const FeatureOptions& features);

}  // namespace seamap
