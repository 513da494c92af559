#pragma once
// Seed 004's enhancement chain in front of a feature front end (VO,
// refinement, stereo): `--feature-enhance off|auto|<chain>`. `auto` measures
// the inliers the front end gets from a few probe images with no chain and
// with each candidate chain, and keeps the best only where the images are
// short of inliers and the chain beats no enhancement clearly: on images that
// match well a chain costs time and accuracy (docs/TERRAIN.md measures both).
// The front end says what an inlier is (the measure callback).
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/enhance/enhance_chain.h"

namespace seamap {

struct FeatureEnhanceOptions {
  std::string spec = "off";  // off | auto | an op list (seamap enhance --ops)
  int probe_frames = 8;      // auto: the first frames (or pairs) it tries the chains on
  double min_gain = 0.1;     // auto: keep a chain only with this many more inliers (share)
  // auto: with this many inliers unenhanced, none is kept without trying
  // chains: more matches from enhanced (noisier) pixels then do not make the
  // motion better (docs/TERRAIN.md: drift 0.83 -> 1.16 % with dehazing that
  // raised the inliers from 573 to 788).
  double enough_inliers = 200;
  // auto: the chains tried, each against none.
  std::vector<std::string> candidates = {"dehaze:gate=false", "colorbalance,dehaze:gate=false",
                                         "flatfield,dehaze:gate=false", "default"};
  void Check() const;  // InputError naming --feature-enhance
};

struct EnhancementTrial {
  std::string chain;    // EnhanceChain::Names()
  double inliers = 0;   // mean per probe pair
  double features = 0;  // mean per image
};

struct EnhancementChoice {
  EnhanceChain chain;                    // empty: none
  std::vector<EnhancementTrial> trials;  // auto: none first, then each candidate
};

// The inliers a front end gets from the probe with `chain` in front (empty: none).
using MeasureWithChain = std::function<EnhancementTrial(const EnhanceChain& chain)>;

// The chain for `options.spec`. `seed` holds the probe's images (the flat
// field's seed; for auto, at least two, else none is chosen); `measure` is
// called for auto only.
EnhancementChoice ChooseEnhancementByInliers(const FeatureEnhanceOptions& options, const std::vector<cv::Mat>& seed,
                                             const MeasureWithChain& measure);

}  // namespace seamap
