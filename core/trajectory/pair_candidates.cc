#include "core/trajectory/pair_candidates.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

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
  // Across lines and loops: the nearest frames in reach, by predicted overlap.
  std::vector<double> radius(n);
  std::vector<cv::Point2d> centre(n);
  double max_radius = 0;
  for (int i = 0; i < n; ++i) {
    radius[i] = Radius(frames[i].footprint);
    centre[i] = Centre(frames[i].footprint);
    if (frames[i].usable) max_radius = std::max(max_radius, radius[i]);
  }
  const double cell_m = std::max(1e-3, 2 * max_radius + options.max_slide_m);
  auto cell_of = [&](double v) { return static_cast<int64_t>(std::floor(v / cell_m)); };
  auto key = [](int64_t x, int64_t y) { return (x << 32) ^ (y & 0xffffffff); };
  std::unordered_map<int64_t, std::vector<int>> grid;
  for (int i = 0; i < n; ++i)
    if (frames[i].usable && std::isfinite(centre[i].x) && std::isfinite(centre[i].y))
      grid[key(cell_of(centre[i].x), cell_of(centre[i].y))].push_back(i);
  struct Cross {
    CandidatePair pair;
    double distance_m;
  };
  std::vector<Cross> cross;
  std::vector<std::pair<double, int>> near;  // (distance, j)
  for (int i = 0; i < n; ++i) {
    if (!frames[i].usable || !std::isfinite(centre[i].x) || !std::isfinite(centre[i].y)) continue;
    near.clear();
    const int64_t cx = cell_of(centre[i].x), cy = cell_of(centre[i].y);
    for (int64_t y = cy - 1; y <= cy + 1; ++y)
      for (int64_t x = cx - 1; x <= cx + 1; ++x) {
        const auto it = grid.find(key(x, y));
        if (it == grid.end()) continue;
        for (int j : it->second) {
          if (j <= i || std::fabs(frames[j].time_s - frames[i].time_s) <= options.min_gap_s) continue;
          const double gap = std::fabs(frames[j].time_s - frames[i].time_s);
          const double slide =
              std::min(options.max_slide_m, 3 * RelativeSigma(options.nav_noise_m, options.drift_m_per_s, gap));
          const cv::Point2d d = centre[j] - centre[i];
          const double distance = std::hypot(d.x, d.y);
          if (distance <= radius[i] + radius[j] + slide) near.emplace_back(distance, j);  // may touch
        }
      }
    const size_t tested = std::min(near.size(), static_cast<size_t>(std::max(0, options.max_tested_per_frame)));
    std::partial_sort(near.begin(), near.begin() + tested, near.end());
    for (size_t k = 0; k < tested; ++k) {
      const int j = near[k].second;
      const double gap = std::fabs(frames[j].time_s - frames[i].time_s);
      const double slide =
          std::min(options.max_slide_m, 3 * RelativeSigma(options.nav_noise_m, options.drift_m_per_s, gap));
      const double overlap = Overlap(frames[i].footprint, frames[j].footprint, slide);
      if (overlap >= options.min_overlap) cross.push_back({{i, j, false, overlap}, near[k].first});
    }
  }
  // Largest predicted overlap first; among equals (a large slide makes many
  // overlaps whole) the nearest as navigated.
  std::sort(cross.begin(), cross.end(), [](const Cross& a, const Cross& b) {
    if (a.pair.overlap != b.pair.overlap) return a.pair.overlap > b.pair.overlap;
    if (a.distance_m != b.distance_m) return a.distance_m < b.distance_m;
    return std::make_pair(a.pair.i, a.pair.j) < std::make_pair(b.pair.i, b.pair.j);
  });
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
      const int i = cross[k].pair.i, j = cross[k].pair.j;
      if (taken[k] || static_cast<int>(partners[i].size()) >= options.max_cross_per_frame ||
          static_cast<int>(partners[j].size()) >= options.max_cross_per_frame)
        continue;
      if (!any_pass && (same_pass(i, j) || same_pass(j, i))) continue;
      taken[k] = true;
      partners[i].push_back(j);
      partners[j].push_back(i);
      pairs.push_back(cross[k].pair);
    }
  return pairs;
}

}  // namespace seamap
