#include "core/stereo/stereo_matcher.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

#include <opencv2/features2d.hpp>

#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

int DistanceSq(const uint8_t* a, const uint8_t* b) {
  int sum = 0;
  for (int k = 0; k < 128; ++k) {
    const int d = static_cast<int>(a[k]) - static_cast<int>(b[k]);
    sum += d * d;
  }
  return sum;
}

}  // namespace

std::string EpipolarCheck::Describe() const {
  char text[200];
  if (row_ok_fraction >= 0.3 && positive_fraction < 0.5)
    std::snprintf(text, sizeof text, "left and right look swapped (%.0f %% of %d matches have negative disparity)",
                  100 * (1 - positive_fraction), matches);
  else if (row_ok_fraction < 0.3)
    std::snprintf(text, sizeof text,
                  "not a stereo pair for this calibration (median row offset %.1f px over %d matches, only %.0f %% "
                  "within 2 px)",
                  median_row_px, matches, 100 * row_ok_fraction);
  else
    std::snprintf(text, sizeof text,
                  "not a stereo pair for this calibration (only %.0f %% of %d matches have positive disparity)",
                  100 * positive_fraction, matches);
  return text;
}

EpipolarCheck CheckEpipolar(const ImageFeatures& left, const ImageFeatures& right, double ratio) {
  EpipolarCheck check;
  if (left.size() < 2 || right.size() < 2) return check;
  // The strongest 500 left keypoints against every right one: enough to see
  // a row offset, and quick.
  const int n = std::min<int>(500, static_cast<int>(left.size()));
  std::vector<std::vector<cv::DMatch>> knn;
  cv::BFMatcher(cv::NORM_L2).knnMatch(left.descriptors.rowRange(0, n), right.descriptors, knn, 2);
  std::vector<double> rows;
  int positive = 0, row_ok = 0;
  for (const auto& m : knn) {
    if (m.size() < 2 || m[0].distance >= ratio * m[1].distance) continue;
    const cv::Point2d l = left.rect_px[m[0].queryIdx], r = right.rect_px[m[0].trainIdx];
    rows.push_back(std::abs(l.y - r.y));
    if (rows.back() <= 2) {
      ++row_ok;
      positive += l.x - r.x > 0;
    }
  }
  check.matches = static_cast<int>(rows.size());
  check.median_row_px = Median(rows);
  check.row_ok_fraction = rows.empty() ? 0 : static_cast<double>(row_ok) / rows.size();
  check.positive_fraction = row_ok ? static_cast<double>(positive) / row_ok : 0;
  return check;
}

std::vector<std::pair<int, int>> MatchAlongRows(const ImageFeatures& left, const ImageFeatures& right,
                                                const RectifiedRig& rig, const StereoMatchOptions& options) {
  const double d_min = rig.f * rig.baseline_m / options.max_depth_m;
  const double d_max = rig.f * rig.baseline_m / options.min_depth_m;
  std::vector<int> by_row(right.size());
  std::iota(by_row.begin(), by_row.end(), 0);
  std::sort(by_row.begin(), by_row.end(), [&](int a, int b) { return right.rect_px[a].y < right.rect_px[b].y; });
  std::vector<double> sorted_rows(by_row.size());
  for (size_t k = 0; k < by_row.size(); ++k) sorted_rows[k] = right.rect_px[by_row[k]].y;

  struct Candidate {
    int right = -1, best = INT32_MAX, second = INT32_MAX;
  };
  std::vector<Candidate> of_left(left.size());
  std::vector<int> right_best(right.size(), INT32_MAX), right_best_left(right.size(), -1);
  for (int l = 0; l < static_cast<int>(left.size()); ++l) {
    const cv::Point2d p = left.rect_px[l];
    const uint8_t* dl = left.descriptors.ptr<uint8_t>(l);
    auto it = std::lower_bound(sorted_rows.begin(), sorted_rows.end(), p.y - options.max_row_px);
    Candidate& c = of_left[l];
    for (size_t k = it - sorted_rows.begin(); k < sorted_rows.size() && sorted_rows[k] <= p.y + options.max_row_px;
         ++k) {
      const int r = by_row[k];
      const double d = p.x - right.rect_px[r].x;
      if (d < d_min || d > d_max) continue;
      const int dist = DistanceSq(dl, right.descriptors.ptr<uint8_t>(r));
      if (dist < c.best) {
        c.second = c.best;
        c.best = dist;
        c.right = r;
      } else if (dist < c.second) {
        c.second = dist;
      }
      if (dist < right_best[r]) right_best[r] = dist, right_best_left[r] = l;
    }
  }
  std::vector<std::pair<int, int>> matches;
  const double ratio_sq = options.ratio * options.ratio;
  for (int l = 0; l < static_cast<int>(left.size()); ++l) {
    const Candidate& c = of_left[l];
    if (c.right < 0 || right_best_left[c.right] != l) continue;  // mutual best
    if (c.second != INT32_MAX && c.best >= ratio_sq * c.second) continue;
    matches.emplace_back(l, c.right);
  }
  return matches;
}

double KeypointSigmaFromRows(const ImageFeatures& left, const ImageFeatures& right,
                             const std::vector<std::pair<int, int>>& matches) {
  std::vector<double> rows;
  for (const auto& [l, r] : matches) rows.push_back(std::abs(left.rect_px[l].y - right.rect_px[r].y));
  // Median |difference| of a gaussian is 0.6745 sigma; the difference of two
  // keypoints has sqrt(2) times a keypoint's sigma.
  return Median(rows) / 0.6745 / std::sqrt(2.0);
}

StereoFrame MakeStereoFrame(const std::string& name, const cv::Mat& left, const cv::Mat& right,
                            const StereoCalibration& calibration, const SiftOptions& sift,
                            const StereoMatchOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  StereoFrame frame;
  frame.name = name;
  frame.left = DetectSift(left, sift);
  frame.right = DetectSift(right, sift);
  frame.left.rect_px = calibration.RectifyLeft(frame.left.raw_px);
  frame.right.rect_px = calibration.RectifyRight(frame.right.raw_px);
  frame.epipolar = CheckEpipolar(frame.left, frame.right, options.ratio);
  if (!frame.epipolar.Passes()) throw InputError("", 0, "pair " + name, frame.epipolar.Describe());

  const RectifiedRig& rig = calibration.rig;
  const auto matches = MatchAlongRows(frame.left, frame.right, rig, options);
  frame.sigma_px = std::max(options.sigma_floor_px, KeypointSigmaFromRows(frame.left, frame.right, matches));
  frame.point_of_left.assign(frame.left.size(), -1);
  for (const auto& [l, r] : matches) {
    StereoPoint p;
    p.left = l;
    p.right = r;
    p.xyz = rig.Triangulate(frame.left.rect_px[l], frame.right.rect_px[r]);
    p.cov = rig.TriangulationCovariance(frame.left.rect_px[l], frame.right.rect_px[r], frame.sigma_px);
    frame.point_of_left[l] = static_cast<int>(frame.points.size());
    frame.points.push_back(p);
  }
  frame.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return frame;
}

}  // namespace seamap
