#include "core/enhance/feature_report.h"

#include <chrono>
#include <cstdio>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>

#include "core/enhance/pixel_format.h"
#include "core/util/error.h"

namespace seamap {
namespace {

struct Detected {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
};

cv::Ptr<cv::Feature2D> MakeDetector(FeatureDetector detector) {
  if (detector == FeatureDetector::kOrb) return cv::ORB::create(5000);  // the default 500 would cap the counts
  return cv::SIFT::create();
}

int CountInliers(const Detected& a, const Detected& b, const std::vector<cv::DMatch>& matches) {
  if (matches.size() < 4) return 0;
  std::vector<cv::Point2f> pa, pb;
  for (const auto& m : matches) {
    pa.push_back(a.keypoints[m.queryIdx].pt);
    pb.push_back(b.keypoints[m.trainIdx].pt);
  }
  cv::Mat inlier_mask;
  cv::Mat h = cv::findHomography(pa, pb, cv::RANSAC, 3.0, inlier_mask, 2000, 0.995);
  return h.empty() ? 0 : cv::countNonZero(inlier_mask);
}

}  // namespace

FeatureDetector ParseFeatureDetector(const std::string& text, const std::string& param) {
  if (text == "sift") return FeatureDetector::kSift;
  if (text == "orb") return FeatureDetector::kOrb;
  throw InputError("", 0, param, "expected 'sift' or 'orb', got '" + text + "'");
}

FeatureStats MeasureFeatures(const std::vector<cv::Mat>& frames, FeatureDetector detector) {
  auto feature2d = MakeDetector(detector);
  cv::BFMatcher matcher(detector == FeatureDetector::kOrb ? cv::NORM_HAMMING : cv::NORM_L2, /*crossCheck=*/true);
  FeatureStats stats;
  Detected previous;
  double features = 0, matches = 0, inliers = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    Detected current;
    feature2d->detectAndCompute(ToGray8(frames[i]), cv::noArray(), current.keypoints, current.descriptors);
    features += current.keypoints.size();
    if (i > 0 && !previous.descriptors.empty() && !current.descriptors.empty()) {
      std::vector<cv::DMatch> found;
      matcher.match(previous.descriptors, current.descriptors, found);
      matches += found.size();
      inliers += CountInliers(previous, current, found);
    }
    previous = std::move(current);
  }
  stats.frames = static_cast<int>(frames.size());
  if (!frames.empty()) stats.features = features / frames.size();
  if (frames.size() > 1) {
    stats.matches = matches / (frames.size() - 1);
    stats.inliers = inliers / (frames.size() - 1);
  }
  return stats;
}

ChainReport ReportChain(const EnhanceChain& chain, const std::vector<cv::Mat>& frames, FeatureDetector detector,
                        const FeatureStats* before) {
  ChainReport report;
  report.chain = chain.Names();
  report.before = before ? *before : MeasureFeatures(frames, detector);
  const size_t seed = std::min(frames.size(), static_cast<size_t>(chain.SeedFrames()));
  chain.Seed(std::vector<cv::Mat>(frames.begin(), frames.begin() + seed));

  std::vector<cv::Mat> enhanced;
  enhanced.reserve(frames.size());
  if (!frames.empty()) chain.Apply(frames.front());  // warm-up: first-call allocations are not per-frame cost
  auto start = std::chrono::steady_clock::now();
  for (const cv::Mat& f : frames) enhanced.push_back(chain.Apply(f));
  double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  report.ms_per_frame = frames.empty() ? 0 : ms / frames.size();
  report.after = MeasureFeatures(enhanced, detector);
  return report;
}

std::string FormatReportTable(const std::vector<ChainReport>& rows, const std::string& detector_name) {
  std::string out;
  char line[256];
  size_t width = 5;
  for (const auto& r : rows) width = std::max(width, r.chain.size());
  const int w = static_cast<int>(width);
  std::snprintf(line, sizeof line, "%-*s  %21s  %21s  %21s  %8s\n", w, "chain",
                (detector_name + " features/frame").c_str(), "matches/pair", "inliers/pair", "ms/frame");
  out += line;
  std::snprintf(line, sizeof line, "%-*s  %21s  %21s  %21s  %8s\n", w, "", "before -> after", "before -> after",
                "before -> after", "");
  out += line;
  for (const auto& r : rows) {
    char f[32], m[32], in[32];
    std::snprintf(f, sizeof f, "%.1f -> %.1f", r.before.features, r.after.features);
    std::snprintf(m, sizeof m, "%.1f -> %.1f", r.before.matches, r.after.matches);
    std::snprintf(in, sizeof in, "%.1f -> %.1f", r.before.inliers, r.after.inliers);
    std::snprintf(line, sizeof line, "%-*s  %21s  %21s  %21s  %8.2f\n", w, r.chain.c_str(), f, m, in, r.ms_per_frame);
    out += line;
  }
  return out;
}

}  // namespace seamap
