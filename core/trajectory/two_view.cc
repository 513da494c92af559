#include "core/trajectory/two_view.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "core/util/statistics.h"

namespace seamap {
namespace {

double RotationAngleDeg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  const double c = std::clamp(((a * b.transpose()).trace() - 1) / 2, -1.0, 1.0);
  return std::acos(c) * 180 / M_PI;
}

// Share of the image the points' convex hull covers.
double HullArea(const std::vector<cv::Point2d>& points, const std::vector<int>& at, const cv::Size& size) {
  if (at.size() < 3) return 0;
  std::vector<cv::Point2f> pts, hull;
  for (int k : at) pts.emplace_back(static_cast<float>(points[k].x), static_cast<float>(points[k].y));
  cv::convexHull(pts, hull);
  return cv::contourArea(hull) / (static_cast<double>(size.width) * size.height);
}

std::vector<int> Indices(const cv::Mat& mask) {
  std::vector<int> out;
  for (int k = 0; k < mask.rows * mask.cols; ++k)
    if (mask.ptr<uchar>()[k]) out.push_back(k);
  return out;
}

Eigen::Vector3d Ray(const cv::Matx33d& k_inv, const cv::Point2d& p) {
  const cv::Vec3d r = k_inv * cv::Vec3d(p.x, p.y, 1);
  return {r[0], r[1], r[2]};
}

// The five-point RANSAC's (R, t) refined by least squares on the Sampson
// error of the inliers in front (the RANSAC model comes from five points).
struct SampsonError {
  SampsonError(const Eigen::Vector3d& x1, const Eigen::Vector3d& x2, double focal) : x1_(x1), x2_(x2), f_(focal) {}
  template <typename T>
  bool operator()(const T* rotation, const T* translation, T* residual) const {
    // E = [t]x R; residual = x2' E x1 / |first two rows of E x1 and E' x2| (in pixels: times f).
    T rx1[3];
    const T x1[3] = {T(x1_.x()), T(x1_.y()), T(x1_.z())};
    ceres::AngleAxisRotatePoint(rotation, x1, rx1);
    const T* t = translation;
    const T ex1[3] = {t[1] * rx1[2] - t[2] * rx1[1], t[2] * rx1[0] - t[0] * rx1[2], t[0] * rx1[1] - t[1] * rx1[0]};
    // E' x2 = R' [t]x' x2 = -R' (t x x2)
    const T tx2[3] = {t[1] * T(x2_.z()) - t[2] * T(x2_.y()), t[2] * T(x2_.x()) - t[0] * T(x2_.z()),
                      t[0] * T(x2_.y()) - t[1] * T(x2_.x())};
    const T minus_rotation[3] = {-rotation[0], -rotation[1], -rotation[2]};
    T et_x2[3];
    ceres::AngleAxisRotatePoint(minus_rotation, tx2, et_x2);
    const T epipolar = T(x2_.x()) * ex1[0] + T(x2_.y()) * ex1[1] + T(x2_.z()) * ex1[2];
    const T norm =
        ceres::sqrt(ex1[0] * ex1[0] + ex1[1] * ex1[1] + et_x2[0] * et_x2[0] + et_x2[1] * et_x2[1] + T(1e-18));
    residual[0] = T(f_) * epipolar / norm;
    return true;
  }
  Eigen::Vector3d x1_, x2_;
  double f_;
};

void RefineEssential(const std::vector<cv::Point2d>& p1, const std::vector<cv::Point2d>& p2, const cv::Mat& use,
                     const cv::Matx33d& k, Eigen::Matrix3d* r, Eigen::Vector3d* t) {
  const cv::Matx33d k_inv = k.inv();
  Eigen::AngleAxisd aa(*r);
  double rotation[3] = {aa.angle() * aa.axis().x(), aa.angle() * aa.axis().y(), aa.angle() * aa.axis().z()};
  double translation[3] = {t->x(), t->y(), t->z()};
  ceres::Problem problem;
  for (int k_ = 0; k_ < use.rows; ++k_) {
    if (!use.at<uchar>(k_)) continue;
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<SampsonError, 1, 3, 3>(
                                 new SampsonError(Ray(k_inv, p1[k_]), Ray(k_inv, p2[k_]), k(0, 0))),
                             new ceres::HuberLoss(1.0), rotation, translation);
  }
  if (problem.NumResidualBlocks() < 8) return;
  problem.SetManifold(translation, new ceres::SphereManifold<3>());
  ceres::Solver::Options options;
  options.max_num_iterations = 20;
  options.linear_solver_type = ceres::DENSE_QR;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  const Eigen::Vector3d axis(rotation[0], rotation[1], rotation[2]);
  *r = axis.norm() > 0 ? Eigen::AngleAxisd(axis.norm(), axis.normalized()).toRotationMatrix()
                       : Eigen::Matrix3d::Identity();
  *t = Eigen::Vector3d(translation[0], translation[1], translation[2]).normalized();
}

// The checks every model must pass besides cheirality.
bool Spread(TwoViewMotion* m, const std::vector<cv::Point2d>& ideal2, const std::vector<int>& inliers,
            const PairGeometry& g, const TwoViewOptions& o) {
  m->inliers = static_cast<int>(inliers.size());
  if (m->inliers < o.min_inliers) {
    m->failure = "too few inliers";
    return false;
  }
  if (m->inliers < o.min_inlier_share * ideal2.size()) {
    m->failure = "inliers are under half of the matches";
    return false;
  }
  if (HullArea(ideal2, inliers, g.image_size) < o.min_area) {
    m->failure = "inliers cover too little of the image";
    return false;
  }
  return true;
}

bool Agrees(TwoViewMotion* m, const PairGeometry& g, const TwoViewOptions& o) {
  m->rotation_error_deg = RotationAngleDeg(m->cam2_from_cam1, g.cam2_from_cam1_ahrs);
  if (m->cheirality < o.min_cheirality) {
    m->failure = "cheirality";
    return false;
  }
  if (m->rotation_error_deg > o.max_rotation_error_deg) {
    m->failure = "rotation disagrees with the AHRS";
    return false;
  }
  return true;
}

// The inliers triangulated with camera 1 at the origin and camera 2 at
// [R | t] (|t| = 1: the unit baseline); points behind camera 1 dropped.
std::vector<Eigen::Vector3d> Triangulate(const std::vector<cv::Point2d>& p1, const std::vector<cv::Point2d>& p2,
                                         const std::vector<int>& use, const cv::Matx33d& k, const Eigen::Matrix3d& r,
                                         const Eigen::Vector3d& t) {
  cv::Matx34d proj1(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0), proj2;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) proj2(i, j) = r(i, j);
    proj2(i, 3) = t(i);
  }
  const cv::Matx33d k_inv = k.inv();
  std::vector<cv::Point2d> n1, n2;
  for (int i : use) {
    const Eigen::Vector3d a = Ray(k_inv, p1[i]), b = Ray(k_inv, p2[i]);
    n1.emplace_back(a.x() / a.z(), a.y() / a.z());
    n2.emplace_back(b.x() / b.z(), b.y() / b.z());
  }
  std::vector<Eigen::Vector3d> points;
  if (n1.empty()) return points;
  cv::Mat homogeneous;
  cv::triangulatePoints(proj1, proj2, n1, n2, homogeneous);
  for (int i = 0; i < homogeneous.cols; ++i) {
    const double w = homogeneous.at<double>(3, i);
    if (std::fabs(w) < 1e-12) continue;
    const Eigen::Vector3d x(homogeneous.at<double>(0, i) / w, homogeneous.at<double>(1, i) / w,
                            homogeneous.at<double>(2, i) / w);
    if (x.z() > 0) points.push_back(x);
  }
  return points;
}

// Metres per unit of baseline: the altitude the points would give the
// altimeter (each beam cast onto the seabed they describe, the vertical
// ranges averaged as a DVL does) set against the measured one. The
// altimeter's position, in the points' unit, depends on the answer: a few
// rounds settle it (its offset is centimetres against metres of range).
std::optional<double> ScaleAtNadir(const std::vector<Eigen::Vector3d>& points, const PairGeometry& g,
                                   const TwoViewOptions& o) {
  const Eigen::Vector3d& n = g.seabed_normal_cam1;
  const Eigen::Vector3d& a_m = g.altimeter_cam1_m;
  const double altitude = g.height_m - n.dot(a_m);  // the altimeter's own range
  const std::vector<Eigen::Vector3d> straight_down = {n};
  const auto& beams = g.altimeter_beams_cam1.empty() ? straight_down : g.altimeter_beams_cam1;
  double scale = 0;
  for (int round = 0; round < (a_m.norm() > 0 ? 3 : 1); ++round) {
    const Eigen::Vector3d a = round == 0 ? Eigen::Vector3d::Zero() : Eigen::Vector3d(a_m / scale);
    double sum = 0;
    int seen = 0;
    for (const Eigen::Vector3d& beam : beams) {
      if (!(n.dot(beam) > 0.1)) continue;
      // Along the beam until it meets the seabed the points describe.
      std::optional<double> below = SeabedDistanceAt(points, n, a, o.nadir_radius);
      for (int step = 0; below && step < 4; ++step) {
        const double along_beam = (*below - n.dot(a)) / n.dot(beam);
        below = SeabedDistanceAt(points, n, a + along_beam * beam, o.nadir_radius);
      }
      if (!below) continue;
      sum += *below - n.dot(a);  // the beam's vertical range
      ++seen;
    }
    // A beam whose footprint no point is near is left out, as a DVL leaves
    // out a beam that loses the bottom.
    if (seen == 0 || !(sum > 0)) return std::nullopt;
    scale = altitude / (sum / seen);
  }
  return scale;
}

TwoViewMotion Homography(const std::vector<cv::Point2d>& p1, const std::vector<cv::Point2d>& p2, const PairGeometry& g,
                         const TwoViewOptions& o) {
  TwoViewMotion m;
  m.model = MotionModel::kHomography;
  cv::Mat mask;
  // MAGSAC++: plain RANSAC's model leaves true inliers out at the image's
  // edges and the translation a few per cent off; refitting to its own
  // inliers keeps that bias.
  cv::Mat h = cv::findHomography(p1, p2, cv::USAC_MAGSAC, o.homography_px, mask, 2000, 0.999);
  if (h.empty()) {
    m.failure = "no homography";
    return m;
  }
  // Then least squares on the points within the threshold, chosen afresh
  // from each fit: the scale settles within a few thousandths.
  std::vector<int> inliers = Indices(mask);
  for (int round = 0; round < 3 && inliers.size() >= 8; ++round) {
    std::vector<cv::Point2d> a, b, moved;
    for (int k : inliers) {
      a.push_back(p1[k]);
      b.push_back(p2[k]);
    }
    const cv::Mat refit = cv::findHomography(a, b, 0);
    if (refit.empty()) break;
    h = refit;
    cv::perspectiveTransform(p1, moved, h);
    inliers.clear();
    for (size_t k = 0; k < p1.size(); ++k)
      if (cv::norm(moved[k] - p2[k]) <= o.homography_px) inliers.push_back(static_cast<int>(k));
  }
  if (!Spread(&m, p2, inliers, g, o)) return m;
  std::vector<cv::Mat> rotations, translations, normals;
  cv::decomposeHomographyMat(h, cv::Mat(g.K), rotations, translations, normals);
  // Of the decompositions, the one whose inliers lie in front of both
  // cameras, with the normal closest to the expected seabed normal.
  const cv::Matx33d k_inv = g.K.inv();
  double best_score = -1;
  for (size_t s = 0; s < rotations.size(); ++s) {
    Eigen::Matrix3d r;
    Eigen::Vector3d t, n;
    cv::cv2eigen(rotations[s], r);
    cv::cv2eigen(translations[s], t);  // t / d
    cv::cv2eigen(normals[s], n);
    if (n.dot(g.seabed_normal_cam1) < 0) continue;  // a plane behind the camera
    // Plane n.X1 = d (d = 1 here): depth1 = 1 / (n.x1); in camera 2 the
    // plane is (R n).X2 = 1 + (R n).t.
    const Eigen::Vector3d n2 = r * n;
    const double d2 = 1 + n2.dot(t);
    int in_front = 0;
    for (int k : inliers) {
      const Eigen::Vector3d x1 = Ray(k_inv, p1[k]), x2 = Ray(k_inv, p2[k]);
      in_front += n.dot(x1) > 0 && n2.dot(x2) * d2 > 0;
    }
    const double cheirality = static_cast<double>(in_front) / inliers.size();
    const double score = cheirality + n.dot(g.seabed_normal_cam1);  // both in [0, 1]
    if (score > best_score) {
      best_score = score;
      m.cam2_from_cam1 = r;
      m.displacement_cam1_m = -g.height_m * (r.transpose() * t);
      m.cheirality = cheirality;
    }
  }
  if (best_score < 0) {
    m.failure = "no decomposition sees the seabed";
    return m;
  }
  if (!Agrees(&m, g, o) || !o.scale_at_nadir) return m;
  // The plane's distance is the view's mean; the altitude is measured below
  // the vehicle. Scale the direction by the points there instead.
  const Eigen::Matrix3d& r = m.cam2_from_cam1;
  const Eigen::Vector3d t = -(r * m.displacement_cam1_m);  // t / d times the height
  if (t.norm() > 1e-12) {
    const Eigen::Vector3d unit = t.normalized();
    if (const auto scale = ScaleAtNadir(Triangulate(p1, p2, inliers, g.K, r, unit), g, o))
      m.displacement_cam1_m = -*scale * (r.transpose() * unit);
  }
  return m;
}

TwoViewMotion Essential(const std::vector<cv::Point2d>& p1, const std::vector<cv::Point2d>& p2, const PairGeometry& g,
                        const TwoViewOptions& o) {
  TwoViewMotion m;
  m.model = MotionModel::kEssential;
  cv::Mat mask;
  const cv::Mat e = cv::findEssentialMat(p1, p2, cv::Mat(g.K), cv::USAC_MAGSAC, 0.999, o.essential_px, mask);
  if (e.empty() || e.rows != 3) {  // several solutions come stacked: a degenerate pair
    m.failure = "no essential matrix";
    return m;
  }
  const std::vector<int> inliers = Indices(mask);
  if (!Spread(&m, p2, inliers, g, o)) return m;
  cv::Mat r_cv, t_cv, front = mask.clone();
  const int in_front = cv::recoverPose(e, p1, p2, cv::Mat(g.K), r_cv, t_cv, front);
  m.cheirality = static_cast<double>(in_front) / inliers.size();
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  cv::cv2eigen(r_cv, r);
  cv::cv2eigen(t_cv, t);  // unit length
  RefineEssential(p1, p2, front, g.K, &r, &t);
  m.cam2_from_cam1 = r;
  if (!Agrees(&m, g, o)) return m;
  // Scale: the triangulated inliers (unit baseline) against the altitude,
  // below the altimeter; the pre-relief way (or where too few points lie
  // near the footprint), the plane through all of them.
  const std::vector<Eigen::Vector3d> points = Triangulate(p1, p2, Indices(front), g.K, r, t);
  if (points.size() < 5) {
    m.failure = "too few triangulated points";
    return m;
  }
  if (o.scale_at_nadir) {
    if (const auto scale = ScaleAtNadir(points, g, o)) {
      m.displacement_cam1_m = -*scale * (r.transpose() * t);
      return m;
    }
  }
  std::vector<double> along;
  for (const auto& x : points) along.push_back(x.dot(g.seabed_normal_cam1));
  const double median = Median(along);
  const auto plane = FitPlane(points, 0.01 * median);
  // A plane far from the seabed's expected tilt is relief, not the seabed
  // (bumps as high as the frame is wide leave no thinnest direction): then
  // the median distance along the expected normal, never the mean.
  const bool plane_ok = plane && plane->normal.dot(g.seabed_normal_cam1) > std::cos(10 * M_PI / 180);
  const double distance = plane_ok ? plane->distance : median;
  m.displacement_cam1_m = -(g.height_m / distance) * (r.transpose() * t);
  return m;
}

}  // namespace

const char* MotionModelName(MotionModel m) {
  switch (m) {
    case MotionModel::kHomography:
      return "homography";
    case MotionModel::kEssential:
      return "essential";
    default:
      return "none";
  }
}

TwoViewMotion EstimateWithModel(MotionModel model, const std::vector<cv::Point2d>& ideal1,
                                const std::vector<cv::Point2d>& ideal2, const PairGeometry& geometry,
                                const TwoViewOptions& options) {
  if (ideal1.size() < 8 || ideal1.size() != ideal2.size()) {
    TwoViewMotion m;
    m.model = model;
    m.failure = "too few matches";
    return m;
  }
  return model == MotionModel::kHomography ? Homography(ideal1, ideal2, geometry, options)
                                           : Essential(ideal1, ideal2, geometry, options);
}

TwoViewMotion ModelSwitch::Next(const std::vector<cv::Point2d>& ideal1, const std::vector<cv::Point2d>& ideal2,
                                const PairGeometry& geometry) {
  auto other = [](MotionModel m) {
    return m == MotionModel::kHomography ? MotionModel::kEssential : MotionModel::kHomography;
  };
  TwoViewMotion first;
  if (in_use_ == MotionModel::kNone) {
    // Choose by inlier counts: a flat seabed gives n_H close to n_E, relief lowers n_H.
    const TwoViewMotion h = EstimateWithModel(MotionModel::kHomography, ideal1, ideal2, geometry, options_);
    const TwoViewMotion e = EstimateWithModel(MotionModel::kEssential, ideal1, ideal2, geometry, options_);
    const double share = h.inliers + e.inliers > 0 ? static_cast<double>(h.inliers) / (h.inliers + e.inliers) : 0;
    const bool h_first = share > options_.homography_share;
    first = h_first ? h : e;
    const TwoViewMotion& second = h_first ? e : h;
    if (first.failure.empty()) {
      in_use_ = first.model;
      return first;
    }
    if (second.failure.empty()) {
      in_use_ = second.model;
      return second;
    }
  } else {
    // The paper's rule: the model in use stays while it passes; on a failure
    // the other is tried and, if it passes, is used from then on.
    first = EstimateWithModel(in_use_, ideal1, ideal2, geometry, options_);
    if (first.failure.empty()) return first;
    const TwoViewMotion second = EstimateWithModel(other(in_use_), ideal1, ideal2, geometry, options_);
    if (second.failure.empty()) {
      in_use_ = second.model;
      return second;
    }
  }
  in_use_ = MotionModel::kNone;
  TwoViewMotion none;
  none.failure = "both models failed (" + first.failure + ")";
  none.inliers = first.inliers;
  return none;
}

std::optional<Plane> FitPlane(const std::vector<Eigen::Vector3d>& points, double tolerance) {
  if (points.size() < 20) return std::nullopt;
  // Least squares (the direction of least spread), then again without the
  // points beyond three robust sigmas of it (or `tolerance`, whichever is
  // larger): seabed relief averages out, stray points are dropped.
  std::vector<int> use(points.size());
  for (size_t k = 0; k < use.size(); ++k) use[k] = static_cast<int>(k);
  Plane plane{Eigen::Vector3d::UnitZ(), 0};
  for (int round = 0; round < 4; ++round) {
    if (use.size() < 20) return std::nullopt;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (int k : use) mean += points[k];
    mean /= static_cast<double>(use.size());
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (int k : use) scatter += (points[k] - mean) * (points[k] - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);
    plane.normal = eigen.eigenvectors().col(0);
    plane.distance = plane.normal.dot(mean);
    if (plane.distance < 0) {
      plane.normal = -plane.normal;
      plane.distance = -plane.distance;
    }
    std::vector<double> residuals;
    for (const auto& p : points) residuals.push_back(std::fabs(plane.normal.dot(p) - plane.distance));
    const double limit = std::max(tolerance, 3 * 1.4826 * Median(residuals));
    use.clear();
    for (size_t k = 0; k < points.size(); ++k)
      if (residuals[k] <= limit) use.push_back(static_cast<int>(k));
  }
  return plane;
}

}  // namespace seamap

namespace seamap {

std::optional<double> SeabedDistanceAt(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& normal,
                                       const Eigen::Vector3d& footprint, double radius_share) {
  constexpr size_t kMinPoints = 20;
  if (points.size() < kMinPoints) return std::nullopt;
  // Axes across the normal; each point as (across, across, along).
  const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
  std::vector<Eigen::Vector3d> local;
  std::vector<double> along, reach;
  for (const auto& x : points) {
    const Eigen::Vector3d d = x - footprint;
    local.emplace_back(u.dot(d), v.dot(d), normal.dot(x));
    along.push_back(normal.dot(x));
    reach.push_back(std::hypot(u.dot(d), v.dot(d)));
  }
  const double typical = Median(along);
  if (!(typical > 0)) return std::nullopt;
  double radius = radius_share * typical;
  std::vector<int> near;
  for (int grow = 0; grow < 6; ++grow, radius *= 1.5) {
    near.clear();
    for (size_t k = 0; k < local.size(); ++k)
      if (reach[k] <= radius) near.push_back(static_cast<int>(k));
    if (near.size() >= kMinPoints) break;
  }
  if (near.size() < kMinPoints) return std::nullopt;
  // along = c0 + c1 u + c2 v (+ c3 u^2 + c4 uv + c5 v^2 where the points
  // allow: a crest or a hollow under the vehicle is curved) by least squares,
  // refitted without the points beyond three robust sigmas (fish,
  // mismatches): c0 is the seabed below the footprint.
  // The quadric only where the points surround the footprint: extrapolated
  // past their edge it bends away.
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (int k : near) centroid += local[k].head<2>();
  centroid /= static_cast<double>(near.size());
  const int terms = near.size() >= 3 * kMinPoints && centroid.norm() < radius / 3 ? 6 : 3;
  auto row = [&](const Eigen::Vector3d& p) {
    Eigen::VectorXd r(terms);
    r.head(3) << 1, p.x(), p.y();
    if (terms == 6) r.tail(3) << p.x() * p.x(), p.x() * p.y(), p.y() * p.y();
    return r;
  };
  Eigen::VectorXd c = Eigen::VectorXd::Zero(terms);
  c(0) = typical;
  std::vector<int> use = near;
  for (int round = 0; round < 3; ++round) {
    if (use.size() < kMinPoints / 2) break;
    Eigen::MatrixXd a(use.size(), terms);
    Eigen::VectorXd b(use.size());
    for (size_t k = 0; k < use.size(); ++k) {
      a.row(k) = row(local[use[k]]).transpose();
      b(k) = local[use[k]].z();
    }
    c = a.colPivHouseholderQr().solve(b);
    std::vector<double> residuals;
    for (int k : near) residuals.push_back(std::fabs(local[k].z() - row(local[k]).dot(c)));
    const double limit = std::max(3 * 1.4826 * Median(residuals), 1e-4 * typical);
    use.clear();
    for (size_t k = 0; k < near.size(); ++k)
      if (residuals[k] <= limit) use.push_back(near[k]);
  }
  return c(0) > 0 ? std::optional<double>(c(0)) : std::nullopt;
}

}  // namespace seamap
