#pragma once
// What an enhancement chain does to feature matching on a sequence of frames:
// features per frame and cross-checked matches between consecutive frames
// (BFMatcher crossCheck), plus how many of those matches fit one homography
// (RANSAC, 3 px) - the matches a mosaic can actually use - and ms per frame.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/enhance/enhance_chain.h"

namespace seamap {

enum class FeatureDetector { kSift, kOrb };

// "sift" or "orb"; anything else -> InputError(field = param).
FeatureDetector ParseFeatureDetector(const std::string& text, const std::string& param);

struct FeatureStats {
  int frames = 0;
  double features = 0;  // mean per frame
  double matches = 0;   // mean cross-checked matches per consecutive pair
  double inliers = 0;   // mean homography inliers per consecutive pair
};

struct ChainReport {
  std::string chain;        // EnhanceChain::Names()
  FeatureStats before;      // raw frames
  FeatureStats after;       // enhanced frames
  double ms_per_frame = 0;  // chain time only
};

// Features and matches on frames as they are (any supported type; detection runs on 8-bit gray).
FeatureStats MeasureFeatures(const std::vector<cv::Mat>& frames, FeatureDetector detector);

// Seeds the chain (SeedFrames() of the frames), enhances every frame, measures both.
// `before` may be passed in to avoid measuring the raw frames for every chain.
ChainReport ReportChain(const EnhanceChain& chain, const std::vector<cv::Mat>& frames, FeatureDetector detector,
                        const FeatureStats* before = nullptr);

// Fixed-width table, one row per chain.
std::string FormatReportTable(const std::vector<ChainReport>& rows, const std::string& detector_name);

}  // namespace seamap
