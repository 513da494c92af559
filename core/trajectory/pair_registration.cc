#include "core/trajectory/pair_registration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <unordered_map>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/trajectory/ground_offsets.h"
#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

// A pair whose matched keypoints moved less than this (median, pixels) while
// the navigation moved more than kMovedGroundPx ground pixels is two copies of one photo.
constexpr double kStillPhotoPx = 0.02;
constexpr double kMovedGroundPx = 20;

struct Match {
  int p, q;  // keypoint of frame i, of frame j
};

int DistanceSq(const uint8_t* a, const uint8_t* b) {
  int sum = 0;
  for (int k = 0; k < 128; ++k) {
    const int d = static_cast<int>(a[k]) - static_cast<int>(b[k]);
    sum += d * d;
  }
  return sum;
}

// Keypoints of a frame by where their ground offsets fall, for searches by radius.
class OffsetGrid {
 public:
  OffsetGrid(const std::vector<cv::Point2d>& offsets, double cell_m) : offsets_(offsets), cell_(cell_m) {
    for (int k = 0; k < static_cast<int>(offsets.size()); ++k) cells_[Key(offsets[k])].push_back(k);
  }
  // Calls visit(k) for keypoints within `radius_m` (<= the cell size) of `at`.
  template <typename Visit>
  void Near(const cv::Point2d& at, double radius_m, Visit visit) const {
    const int64_t cx = Cell(at.x), cy = Cell(at.y);
    for (int64_t y = cy - 1; y <= cy + 1; ++y)
      for (int64_t x = cx - 1; x <= cx + 1; ++x) {
        auto it = cells_.find(Pack(x, y));
        if (it == cells_.end()) continue;
        for (int k : it->second) {
          const cv::Point2d d = offsets_[k] - at;
          if (d.dot(d) <= radius_m * radius_m) visit(k);
        }
      }
  }

 private:
  int64_t Cell(double v) const { return static_cast<int64_t>(std::floor(v / cell_)); }
  static int64_t Pack(int64_t x, int64_t y) { return (x << 32) ^ (y & 0xffffffff); }
  int64_t Key(const cv::Point2d& p) const { return Pack(Cell(p.x), Cell(p.y)); }
  const std::vector<cv::Point2d>& offsets_;
  double cell_;
  std::unordered_map<int64_t, std::vector<int>> cells_;
};

// The best match of descriptor `d` among candidates, by Lowe's ratio; -1 if none passes.
template <typename ForEachCandidate>
int BestByRatio(const uint8_t* d, const cv::Mat& descriptors, double ratio, ForEachCandidate for_each) {
  int best = -1, best_d = INT32_MAX, second_d = INT32_MAX;
  for_each([&](int k) {
    const int dist = DistanceSq(d, descriptors.ptr<uint8_t>(k));
    if (dist < best_d) {
      second_d = best_d;
      best_d = dist;
      best = k;
    } else if (dist < second_d) {
      second_d = dist;
    }
  });
  if (best < 0) return -1;
  // On squared distances: d1 < ratio * d2  <=>  d1^2 < ratio^2 * d2^2.
  if (second_d != INT32_MAX && best_d >= ratio * ratio * second_d) return -1;
  return best;
}

std::vector<int> RansacRigid(const std::vector<cv::Point2d>& p, const std::vector<cv::Point2d>& q, double threshold_m,
                             int iterations, std::mt19937& rng) {
  std::vector<int> best;
  const int n = static_cast<int>(p.size());
  if (n < 2) return best;
  std::uniform_int_distribution<int> pick(0, n - 1);
  for (int it = 0; it < iterations; ++it) {
    const int a = pick(rng), b = pick(rng);
    const cv::Point2d vp = p[b] - p[a], vq = q[b] - q[a];
    if (a == b || vq.dot(vq) < 1e-8) continue;
    // Rot(psi) turns clockwise by psi: angle(Rot(psi) v) = angle(v) - psi.
    const double dpsi = std::atan2(vq.y, vq.x) - std::atan2(vp.y, vp.x);
    const cv::Point2d dt = p[a] - RotateClockwise(q[a], dpsi);
    std::vector<int> inliers;
    for (int k = 0; k < n; ++k) {
      const cv::Point2d r = p[k] - dt - RotateClockwise(q[k], dpsi);
      if (r.dot(r) <= threshold_m * threshold_m) inliers.push_back(k);
    }
    if (inliers.size() > best.size()) best = std::move(inliers);
  }
  return best;
}

template <typename T>
std::vector<T> Pick(const std::vector<T>& v, const std::vector<int>& at) {
  std::vector<T> out;
  out.reserve(at.size());
  for (int k : at) out.push_back(v[k]);
  return out;
}

}  // namespace

void RegistrationOptions::Check() const {
  if (!(ratio > 0 && ratio <= 1)) throw InputError("", 0, "ratio", "expected a number in (0, 1]");
  if (!(inlier_ground_px > 0)) throw InputError("", 0, "inlier_ground_px", "expected a number > 0");
  if (min_inliers < 3) throw InputError("", 0, "min_inliers", "expected at least 3");
  if (!(gate > 0)) throw InputError("", 0, "gate", "expected a number > 0");
  if (!(parallax_share >= 0 && parallax_share < 1))
    throw InputError("", 0, "parallax_share", "expected a number in [0, 1)");
  if (!(epipolar_px > 0)) throw InputError("", 0, "epipolar_px", "expected a number > 0");
}

Rigid2D FitRigid(const std::vector<cv::Point2d>& p, const std::vector<cv::Point2d>& q) {
  cv::Point2d mp(0, 0), mq(0, 0);
  for (size_t k = 0; k < p.size(); ++k) {
    mp += p[k];
    mq += q[k];
  }
  mp *= 1.0 / p.size();
  mq *= 1.0 / q.size();
  // Rotation by theta counter-clockwise that best maps centred q onto centred p (Kabsch in 2D).
  double sin_sum = 0, cos_sum = 0;
  for (size_t k = 0; k < p.size(); ++k) {
    const cv::Point2d a = q[k] - mq, b = p[k] - mp;
    cos_sum += a.x * b.x + a.y * b.y;
    sin_sum += a.x * b.y - a.y * b.x;
  }
  Rigid2D r;
  r.dpsi = -std::atan2(sin_sum, cos_sum);  // clockwise
  r.dt = mp - RotateClockwise(mq, r.dpsi);
  return r;
}

PairRegistration RegisterPair(const RegistrationFrame& fi, const RegistrationFrame& fj, const RelativeNavNoise& noise,
                              const RegistrationOptions& options, uint64_t seed) {
  PairRegistration out;
  const FrameFeatures& a = *fi.features;
  const FrameFeatures& b = *fj.features;
  if (a.ideal_px.size() < 10 || b.ideal_px.size() < 10) {
    out.reason = "too few keypoints";
    return out;
  }
  if (SameFeatures(a, b)) {
    out.reason = "identical frames (the same photo twice: a frozen camera?)";
    return out;
  }
  std::mt19937 rng(static_cast<uint32_t>(seed));
  const double ground_px = std::max(fi.ground_px_m, fj.ground_px_m);
  const double threshold = options.inlier_ground_px * ground_px;
  // The navigation's prediction of the motion.
  const cv::Point2d baseline = fj.position_m - fi.position_m;
  const Rigid2D nav{RotateClockwise(baseline, -fi.heading_rad), WrapAngle(fj.heading_rad - fi.heading_rad)};
  double reach = 0;  // how far a keypoint of j may be from its predicted place in i (3 sigma)
  for (const auto& o : fj.offsets) reach = std::max(reach, std::hypot(o.x, o.y));
  const double search_m = 3 * (noise.position_m + (reach + std::hypot(baseline.x, baseline.y)) * noise.heading_rad);
  // How far relief may move a point between the two views (0 on a flat seabed).
  const bool relief = options.parallax_share > 0;
  const double parallax_m = options.parallax_share * (std::hypot(baseline.x, baseline.y) + 3 * noise.position_m);

  // 1. A rough motion: the navigation's when it is good to a few tens of
  // ground pixels, else from the strongest keypoints of j matched unguided.
  Rigid2D rough = nav;
  double rough_radius = search_m + 5 * ground_px;
  if (search_m > 30 * ground_px) {
    std::vector<cv::Point2d> p, q;
    const int seeds = std::min<int>(options.seed_keypoints, static_cast<int>(b.ideal_px.size()));
    for (int k = 0; k < seeds; ++k) {
      const int best = BestByRatio(b.descriptors.ptr<uint8_t>(k), a.descriptors, options.ratio, [&](auto visit) {
        for (int m = 0; m < a.descriptors.rows; ++m) visit(m);
      });
      if (best < 0) continue;
      p.push_back(fi.offsets[best]);
      q.push_back(fj.offsets[k]);
    }
    const std::vector<int> inliers = RansacRigid(p, q, 2 * threshold + parallax_m / 2, options.ransac_iterations, rng);
    if (static_cast<int>(inliers.size()) < std::max(6, options.min_inliers / 3)) {
      out.reason = "no consistent matches among the strongest keypoints";
      out.matches = static_cast<int>(p.size());
      return out;
    }
    rough = FitRigid(Pick(p, inliers), Pick(q, inliers));
    rough_radius = 8 * ground_px;
  }
  rough_radius += parallax_m;

  // 2. Every keypoint of j near where the rough motion puts it in i.
  const OffsetGrid grid(fi.offsets, rough_radius);
  std::vector<cv::Point2d> p, q;
  std::vector<std::pair<int, int>> matched;  // keypoint indices
  for (int k = 0; k < static_cast<int>(fj.offsets.size()); ++k) {
    const cv::Point2d at = rough.dt + RotateClockwise(fj.offsets[k], rough.dpsi);
    const int best = BestByRatio(b.descriptors.ptr<uint8_t>(k), a.descriptors, options.ratio,
                                 [&](auto visit) { grid.Near(at, rough_radius, visit); });
    if (best < 0) continue;
    p.push_back(fi.offsets[best]);
    q.push_back(fj.offsets[k]);
    matched.emplace_back(best, k);
  }
  out.matches = static_cast<int>(p.size());
  std::vector<int> inliers;
  if (!relief) {
    inliers = RansacRigid(p, q, threshold, options.ransac_iterations, rng);
  } else if (p.size() >= 8) {
    // One relative camera motion, whatever the height of each point.
    std::vector<cv::Point2f> pi, pj;
    for (const auto& m : matched) {
      pi.push_back(a.ideal_px[m.first]);
      pj.push_back(b.ideal_px[m.second]);
    }
    cv::setRNGSeed(static_cast<int>(seed & 0x7fffffff));
    cv::Mat mask;
    const cv::Mat e = cv::findEssentialMat(pi, pj, cv::Mat(fi.k), cv::RANSAC, 0.999, options.epipolar_px, mask);
    if (!e.empty() && !mask.empty())
      for (int k = 0; k < mask.rows * mask.cols; ++k)
        if (mask.at<uint8_t>(k)) inliers.push_back(k);
  }
  if (static_cast<int>(inliers.size()) < options.min_inliers) {
    out.reason = "too few inliers";
    out.inliers = static_cast<int>(inliers.size());
    return out;
  }
  // 3. Refit on the inliers, and once more on those of the refit (planar only:
  // on relief the rigid motion is an approximation and keeps every inlier).
  Rigid2D fit = FitRigid(Pick(p, inliers), Pick(q, inliers));
  for (int round = 0; round < (relief ? 0 : 2); ++round) {
    std::vector<int> again;
    for (int k = 0; k < static_cast<int>(p.size()); ++k) {
      const cv::Point2d r = p[k] - fit.dt - RotateClockwise(q[k], fit.dpsi);
      if (r.dot(r) <= threshold * threshold) again.push_back(k);
    }
    if (static_cast<int>(again.size()) < options.min_inliers) break;
    inliers = std::move(again);
    fit = FitRigid(Pick(p, inliers), Pick(q, inliers));
  }
  out.inliers = static_cast<int>(inliers.size());
  out.dt_east_m = fit.dt.x;
  out.dt_north_m = fit.dt.y;
  out.dheading_rad = WrapAngle(fit.dpsi);

  // Residuals, spread and covariance: S = s^2 (J^T J)^-1 over the inliers.
  double sum_sq = 0;
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
  std::vector<cv::Point2f> hull_points;
  const double c = std::cos(fit.dpsi), s = std::sin(fit.dpsi);
  for (int k : inliers) {
    const cv::Point2d r = p[k] - fit.dt - RotateClockwise(q[k], fit.dpsi);
    sum_sq += r.dot(r);
    // d(residual)/d(dt) = -I; d/d(dpsi) = -dRot/dpsi q, dRot/dpsi = [[-s, c], [-c, -s]].
    Eigen::Matrix<double, 2, 3> j;
    j << -1, 0, -(-s * q[k].x + c * q[k].y), 0, -1, -(-c * q[k].x - s * q[k].y);
    jtj += j.transpose() * j;
    hull_points.emplace_back(static_cast<float>(p[k].x), static_cast<float>(p[k].y));
  }
  out.rms_m = std::sqrt(sum_sq / inliers.size());
  // The photos did not move while the navigation says the vehicle did: a
  // camera repeating its last photo (re-encoded, or with its noise), not a
  // measurement of the motion. Real keypoints of two exposures differ by
  // their noise, a few tenths of a pixel; these differ by nothing.
  std::vector<double> moved_px;
  for (int k : inliers) moved_px.push_back(cv::norm(a.ideal_px[matched[k].first] - b.ideal_px[matched[k].second]));
  const double baseline_m = std::hypot(baseline.x, baseline.y);
  if (Median(moved_px) < kStillPhotoPx && baseline_m > kMovedGroundPx * ground_px) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "no parallax: the photos did not move while the navigation moved (median %.3f px for %.3f m)",
                  Median(moved_px), baseline_m);
    out.reason = text;
    return out;
  }
  const double sigma = std::max(out.rms_m, 0.3 * ground_px);
  out.covariance = sigma * sigma * jtj.inverse();

  std::vector<cv::Point2f> hull;
  cv::convexHull(hull_points, hull);
  const double spread = cv::contourArea(hull) / std::max(1e-9, fi.footprint_m2);
  if (static_cast<double>(out.inliers) < options.min_inlier_share * out.matches) {
    out.reason = "inliers are under a quarter of the matches";
  } else if (spread < options.min_spread) {
    out.reason = "inliers bunched in a corner of the frame";
  } else {
    // Agreement with the navigation, within its noise and the fit's.
    Eigen::Vector3d d(fit.dt.x - nav.dt.x, fit.dt.y - nav.dt.y, WrapAngle(fit.dpsi - nav.dpsi));
    const double lever = std::hypot(baseline.x, baseline.y) * noise.heading_rad;
    Eigen::Matrix3d cov = out.covariance;
    cov(0, 0) += noise.position_m * noise.position_m + lever * lever;
    cov(1, 1) += noise.position_m * noise.position_m + lever * lever;
    cov(2, 2) += noise.heading_rad * noise.heading_rad;
    const double mahalanobis = d.dot(cov.inverse() * d);
    if (mahalanobis > options.gate) {
      out.reason = "disagrees with the navigation (Mahalanobis^2 " + std::to_string(mahalanobis) + ")";
    } else {
      out.accepted = true;
      out.inlier_matches = Pick(matched, inliers);
    }
  }
  return out;
}

}  // namespace seamap
