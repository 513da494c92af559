#include "core/trajectory/pair_candidates.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace seamap {
namespace {

cv::Point2d Centre(const std::array<cv::Point2d, 4>& f) {
  return (f[0] + f[1] + f[2] + f[3]) * 0.25;
}

std::vector<cv::Point2f> Polygon(const std::array<cv::Point2d, 4>& f, const cv::Point2d& shift) {
  std::vector<cv::Point2f> out;
  for (const auto& c : f) out.emplace_back(static_cast<float>(c.x + shift.x), static_cast<float>(c.y + shift.y));
  return out;
}

// Share of a's area that b, moved up to `slide` towards a, covers.
double Overlap(const std::array<cv::Point2d, 4>& a, const std::array<cv::Point2d, 4>& b, double slide) {
  const cv::Point2d towards = Centre(a) - Centre(b);
  const double distance = std::hypot(towards.x, towards.y);
  const cv::Point2d shift = distance > 0 ? towards * (std::min(slide, distance) / distance) : cv::Point2d(0, 0);
  // Local coordinates about a's centre keep float precision.
  const cv::Point2d origin = Centre(a);
  std::vector<cv::Point2f> pa = Polygon(a, -origin), pb = Polygon(b, shift - origin), common;
  const double area = std::fabs(cv::contourArea(pa));
  if (area <= 0) return 0;
  return cv::intersectConvexConvex(pa, pb, common, true) / area;
}

double Radius(const std::array<cv::Point2d, 4>& f) {
  const cv::Point2d c = Centre(f);
  double r = 0;
  for (const auto& p : f) r = std::max(r, std::hypot(p.x - c.x, p.y - c.y));
  return r;
}

}  // namespace

double RelativeSigma(double nav_noise_m, double drift_m_per_s, double dt_s) {
  return std::sqrt(2 * nav_noise_m * nav_noise_m + std::pow(drift_m_per_s * dt_s, 2));
}

std::vector<CandidatePair> FindCandidatePairs(const std::vector<CandidateFrame>& frames,
                                              const CandidateOptions& options) {
  const int n = static_cast<int>(frames.size());
  std::vector<CandidatePair> pairs;
  for (int i = 0; i < n; ++i) {
    if (!frames[i].usable) continue;
    for (int j = i + 1; j <= std::min(n - 1, i + 2); ++j) {
      if (!frames[j].usable || std::fabs(frames[j].time_s - frames[i].time_s) > options.min_gap_s) continue;
      const double overlap = Overlap(frames[i].footprint, frames[j].footprint, 0);
      if (overlap > 0) pairs.push_back({i, j, true, overlap});
    }
  }
  // Across lines and loops: every pair that may overlap enough, by predicted overlap.
  std::vector<double> radius(n);
  std::vector<cv::Point2d> centre(n);
  for (int i = 0; i < n; ++i) {
    radius[i] = Radius(frames[i].footprint);
    centre[i] = Centre(frames[i].footprint);
  }
  std::vector<CandidatePair> cross;
  for (int i = 0; i < n; ++i) {
    if (!frames[i].usable) continue;
    for (int j = i + 1; j < n; ++j) {
      const double gap = std::fabs(frames[j].time_s - frames[i].time_s);
      if (!frames[j].usable || gap <= options.min_gap_s) continue;
      const double slide = 3 * RelativeSigma(options.nav_noise_m, options.drift_m_per_s, gap);
      const cv::Point2d d = centre[j] - centre[i];
      if (std::hypot(d.x, d.y) > radius[i] + radius[j] + slide) continue;  // cannot touch
      const double overlap = Overlap(frames[i].footprint, frames[j].footprint, slide);
      if (overlap >= options.min_overlap) cross.push_back({i, j, false, overlap});
    }
  }
  std::stable_sort(cross.begin(), cross.end(), [](const auto& a, const auto& b) { return a.overlap > b.overlap; });
  // At most max_cross_per_frame partners a frame, spread over passes (a
  // partner within min_gap_s of one taken is on the same pass): first the
  // best pair of each pass, then the best of the rest.
  std::vector<std::vector<int>> partners(n);
  auto same_pass = [&](int frame, int other) {
    for (int k : partners[frame])
      if (std::fabs(frames[k].time_s - frames[other].time_s) <= options.min_gap_s) return true;
    return false;
  };
  std::vector<bool> taken(cross.size(), false);
  for (const bool any_pass : {false, true})
    for (size_t k = 0; k < cross.size(); ++k) {
      const int i = cross[k].i, j = cross[k].j;
      if (taken[k] || static_cast<int>(partners[i].size()) >= options.max_cross_per_frame ||
          static_cast<int>(partners[j].size()) >= options.max_cross_per_frame)
        continue;
      if (!any_pass && (same_pass(i, j) || same_pass(j, i))) continue;
      taken[k] = true;
      partners[i].push_back(j);
      partners[j].push_back(i);
      pairs.push_back(cross[k]);
    }
  return pairs;
}

}  // namespace seamap
