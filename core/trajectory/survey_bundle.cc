#include "core/trajectory/survey_bundle.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <unordered_map>

#include <ceres/ceres.h>
#include <ceres/dynamic_autodiff_cost_function.h>
#include <Eigen/Dense>

#include "core/camera/frame_projector.h"
#include "core/geo/rotation.h"
#include "core/trajectory/nav_priors.h"
#include "core/util/error.h"

namespace seamap {
namespace {

constexpr double kDegToRad = M_PI / 180;

// [east_m, north_m, up_m, heading_rad, pitch_rad, roll_rad]: one Ceres block per frame.
using PoseBlock = std::array<double, 6>;
using PointBlock = std::array<double, 3>;  // east, north, up

// NedFromBody = Rz(heading) Ry(pitch) Rx(roll) (core/geo/rotation.h), row-major 3x3.
template <typename T>
void NedFromBodyRad(const T& heading, const T& pitch, const T& roll, T m[9]) {
  using std::cos;
  using std::sin;
  const T ch = cos(heading), sh = sin(heading), cp = cos(pitch), sp = sin(pitch), cr = cos(roll), sr = sin(roll);
  m[0] = ch * cp;
  m[1] = ch * sp * sr - sh * cr;
  m[2] = ch * sp * cr + sh * sr;
  m[3] = sh * cp;
  m[4] = sh * sp * sr + ch * cr;
  m[5] = sh * sp * cr - ch * sr;
  m[6] = -sp;
  m[7] = cp * sr;
  m[8] = cp * cr;
}

constexpr double kMinDepthM = 1e-3;    // nearest a point may be to a camera
constexpr double kMinBeamRate = 0.05;  // steepest a beam may meet its plane: range per unit of height
// The point in the camera, normalised, against the observation; whitened.
struct ReprojectionResidual {
  Eigen::Matrix3d body_from_camera;
  Eigen::Vector3d mount_offset_m;  // body frame
  double x, y;                     // observed, normalised
  double inv_sigma_x, inv_sigma_y;

  // The point in the camera frame (OpenCV axes), metres.
  template <typename T>
  void InCamera(const T* pose, const T* point, T* d_cam) const {
    T r_nb[9];
    NedFromBodyRad(pose[3], pose[4], pose[5], r_nb);
    // Camera centre in NED (north, east, down) and the point relative to it.
    T centre[3], d_ned[3];
    centre[0] = pose[1];
    centre[1] = pose[0];
    centre[2] = -pose[2];
    for (int r = 0; r < 3; ++r)
      centre[r] +=
          r_nb[3 * r] * mount_offset_m(0) + r_nb[3 * r + 1] * mount_offset_m(1) + r_nb[3 * r + 2] * mount_offset_m(2);
    d_ned[0] = point[1] - centre[0];
    d_ned[1] = point[0] - centre[1];
    d_ned[2] = -point[2] - centre[2];
    // Body, then camera: X_c = B^T R_nb^T d.
    T d_body[3];
    for (int c = 0; c < 3; ++c) d_body[c] = r_nb[c] * d_ned[0] + r_nb[3 + c] * d_ned[1] + r_nb[6 + c] * d_ned[2];
    for (int c = 0; c < 3; ++c)
      d_cam[c] =
          body_from_camera(0, c) * d_body[0] + body_from_camera(1, c) * d_body[1] + body_from_camera(2, c) * d_body[2];
  }

  template <typename T>
  bool operator()(const T* pose, const T* point, T* residual) const {
    T d_cam[3];
    InCamera(pose, point, d_cam);
    // A point at or behind the camera gets a huge but finite residual (the
    // robust loss makes it an outlier), never a failed evaluation: one failed
    // residual rejects the whole step, and in a large survey that can happen
    // in every step (see BeamAltitudeResidual).
    const T depth = d_cam[2] > T(kMinDepthM) ? d_cam[2] : T(kMinDepthM);
    residual[0] = (d_cam[0] / depth - x) * inv_sigma_x;
    residual[1] = (d_cam[1] / depth - y) * inv_sigma_y;
    return true;
  }
};

// One component of the pose against an absolute measurement (angles wrapped).
struct AbsoluteResidual {
  int index;
  double value, inv_sigma;
  bool angle;
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    const T d = pose[index] - value;
    residual[0] = (angle ? WrapAngle(d) : d) * inv_sigma;
    return true;
  }
};

// The seabed under one DVL beam: a local plane, height_up_m + slope . (east, north
// offset from the beam's footprint as first placed); one Ceres block
// [height, slope east, slope north] per beam and frame. Points tie into it by
// one residual each, and the altimeter by the vehicle's height above it, so
// that every residual holds at most one point and Ceres eliminates them all.
using BeamBlock = std::array<double, 3>;

// A tracked point near a beam's footprint lies on its plane, up to the
// seabed's curvature over the neighbourhood (sigma).
struct BeamPlaneResidual {
  double anchor_east_m, anchor_north_m, inv_sigma_m;
  template <typename T>
  bool operator()(const T* plane, const T* point, T* residual) const {
    const T predicted = plane[0] + plane[1] * (point[0] - anchor_east_m) + plane[2] * (point[1] - anchor_north_m);
    residual[0] = (point[2] - predicted) * inv_sigma_m;
    return true;
  }
};

// The altimeter: the mean vertical range of its beams, each cast from the
// current pose onto its beam's plane (the beam's direction in the body frame).
struct BeamAltitudeResidual {
  double altitude_m, inv_sigma_m;
  std::vector<Eigen::Vector3d> beams_body;  // unit directions, body frame (x forward, y starboard, z down)
  std::vector<Eigen::Vector2d> anchors;     // (east, north) of each plane's anchor
  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    const T* pose = blocks[0];
    T r_nb[9];
    NedFromBodyRad(pose[3], pose[4], pose[5], r_nb);
    T range_sum = T(0);
    for (size_t b = 0; b < beams_body.size(); ++b) {
      const Eigen::Vector3d& v = beams_body[b];
      const T north = r_nb[0] * v(0) + r_nb[1] * v(1) + r_nb[2] * v(2);
      const T east = r_nb[3] * v(0) + r_nb[4] * v(1) + r_nb[5] * v(2);
      const T up = -(r_nb[6] * v(0) + r_nb[7] * v(1) + r_nb[8] * v(2));
      const T* plane = blocks[b + 1];
      // pose + t (east, north, up) on the plane: t = (plane at the pose - pose up) / (up - slope . (east, north)).
      const T below =
          plane[0] + plane[1] * (pose[0] - anchors[b].x()) + plane[2] * (pose[1] - anchors[b].y()) - pose[2];
      // A beam grazing its plane (a slope the solve tilted too far) reads a
      // long but finite range, never a failed evaluation: one failure rejects
      // the whole step, and with thousands of beam planes some plane grazed in
      // almost every step, so the trust region shrank until the solve stopped
      // far from the answer (docs/TERRAIN.md, "rugged seed 2").
      T rate = up - plane[1] * east - plane[2] * north;
      if (!(rate < T(-kMinBeamRate))) rate = T(-kMinBeamRate);
      range_sum += -(below / rate) * up;
    }
    residual[0] = (range_sum / static_cast<double>(beams_body.size()) - altitude_m) * inv_sigma_m;
    return true;
  }
};

// The least-squares plane through (offset_m, z_m): height at offset 0 and
// slopes; slopes 0 (the mean height) when the offsets do not span an area.
Eigen::Vector3d FitPlane(const std::vector<Eigen::Vector2d>& offsets, const std::vector<double>& z, bool* spans) {
  *spans = false;
  double mean = 0;
  for (double v : z) mean += v;
  mean /= static_cast<double>(z.size());
  if (offsets.size() >= 4) {
    Eigen::MatrixXd a(offsets.size(), 3);
    Eigen::VectorXd b(offsets.size());
    for (size_t m = 0; m < offsets.size(); ++m) {
      a.row(m) << 1, offsets[m].x(), offsets[m].y();
      b(m) = z[m];
    }
    const Eigen::Matrix3d ata = a.transpose() * a;
    const double n = static_cast<double>(offsets.size());
    const Eigen::Matrix2d spread = ata.block<2, 2>(1, 1) / n - ata.block<2, 1>(1, 0) * ata.block<1, 2>(0, 1) / (n * n);
    if (spread.determinant() > 1e-8) {
      const Eigen::Vector3d plane = ata.ldlt().solve(a.transpose() * b);
      // A far extrapolation amplifies noise: only an interpolation-like plane is kept.
      const Eigen::VectorXd row = (ata.inverse() * a.transpose()).row(0);
      if (row.cwiseAbs().sum() < 3 && std::abs(plane(1)) < 1.5 && std::abs(plane(2)) < 1.5) {
        *spans = true;
        return plane;
      }
    }
  }
  return Eigen::Vector3d(mean, 0, 0);
}

void Require(bool ok, const char* option, const char* expected) {
  if (!ok) throw InputError("", 0, option, expected);
}

// SPARSE_SCHUR with the first sparse library there is, else (or when asked)
// ITERATIVE_SCHUR: conjugate gradients, the frames' diagonal blocks of the
// reduced system as preconditioner, nothing factored.
void ChooseLinearSolver(bool iterative, ceres::Solver::Options* solver, std::string* name) {
  for (ceres::SparseLinearAlgebraLibraryType library : {ceres::SUITE_SPARSE, ceres::EIGEN_SPARSE, ceres::CX_SPARSE}) {
    if (!iterative && ceres::IsSparseLinearAlgebraLibraryTypeAvailable(library)) {
      solver->linear_solver_type = ceres::SPARSE_SCHUR;
      solver->sparse_linear_algebra_library_type = library;
      *name = std::string("SPARSE_SCHUR/") + ceres::SparseLinearAlgebraLibraryTypeToString(library);
      return;
    }
  }
  solver->linear_solver_type = ceres::ITERATIVE_SCHUR;
  solver->preconditioner_type = ceres::SCHUR_JACOBI;
  *name = "ITERATIVE_SCHUR/SCHUR_JACOBI";
}

PoseBlock BlockFrom(const VehiclePose& p) {
  return {p.east_m, p.north_m, -p.depth_m, p.heading_deg * kDegToRad, p.pitch_deg * kDegToRad, p.roll_deg * kDegToRad};
}

struct Solved {
  double initial_cost = 0, final_cost = 0;
  int iterations = 0;
  bool converged = false;
};

// Reprojection error of one observation in pixels (x and y scaled by fx, fy), or +inf behind the camera.
double ErrorPx(const ReprojectionResidual& r, const PoseBlock& pose, const PointBlock& point, double pixel_sigma) {
  double d_cam[3], residual[2];
  r.InCamera(pose.data(), point.data(), d_cam);
  if (!(d_cam[2] > kMinDepthM)) return HUGE_VAL;  // at or behind the camera
  r(pose.data(), point.data(), residual);
  return pixel_sigma * std::hypot(residual[0], residual[1]);
}

}  // namespace

void SurveyBundleOptions::Check() const {
  auto finite_non_negative = [](double v) { return v >= 0 && std::isfinite(v); };
  auto positive = [](double v) { return v > 0 && std::isfinite(v); };
  Require(finite_non_negative(nav_sigma_m), "--nav-noise", "expected metres >= 0");
  Require(finite_non_negative(nav_drift_m_per_s), "--nav-drift", "expected metres per minute >= 0");
  Require(finite_non_negative(heading_sigma_rad), "--heading-noise", "expected degrees >= 0");
  Require(positive(attitude_sigma_rad), "--attitude-noise", "expected degrees > 0");
  Require(positive(depth_sigma_m), "--depth-noise", "expected metres > 0");
  Require(positive(altitude_sigma_m), "--altitude-noise", "expected metres > 0");
  Require(positive(pixel_sigma), "pixel_sigma", "expected pixels > 0");
  Require(positive(reprojection_loss_scale), "reprojection_loss_scale", "expected a number > 0");
  Require(positive(prior_loss_scale), "prior_loss_scale", "expected a number > 0");
  Require(positive(reject_px), "reject_px", "expected pixels > 0");
  Require(max_iterations >= 1, "max_iterations", "expected at least 1");
  Require(altitude_points >= 1, "altitude_points", "expected at least 1");
  Require(positive(beam_plane_sigma_share), "beam_plane_sigma_share", "expected a number > 0");
  Require(dvl_beam_angle_deg >= 0 && dvl_beam_angle_deg < 60, "dvl_beam_angle_deg", "expected degrees in [0, 60)");
  Require(finite_non_negative(drift_knot_s), "drift_knot_s", "expected seconds >= 0");
  Require(threads >= 1, "threads", "expected at least 1");
  Require(finite_non_negative(held_sigma_m) && finite_non_negative(held_sigma_deg) &&
              (held_sigma_m > 0) == (held_sigma_deg > 0),
          "held_sigma_m", "expected metres and degrees >= 0, both 0 or neither");
}

std::optional<Eigen::Vector3d> FlatSeabedPoint(const CameraModel& camera, const VehiclePose& pose,
                                               const cv::Point2f& ideal_px) {
  const Eigen::Matrix3d r_nb = NedFromBody(pose);
  const Eigen::Vector3d ray =
      r_nb * camera.BodyFromCamera() *
      Eigen::Vector3d((ideal_px.x - camera.cx) / camera.fx, (ideal_px.y - camera.cy) / camera.fy, 1);
  const Eigen::Vector3d centre =
      Eigen::Vector3d(pose.north_m, pose.east_m, pose.depth_m) + r_nb * camera.mount_offset_m;
  const double seabed_down = pose.depth_m + pose.altitude_m;
  if (!(ray.z() > 1e-3 * ray.norm()) || !(seabed_down > centre.z())) return std::nullopt;
  const Eigen::Vector3d hit = centre + ray * ((seabed_down - centre.z()) / ray.z());
  return Eigen::Vector3d(hit.y(), hit.x(), -hit.z());
}

SurveyBundleResult SolveSurveyBundle(const std::vector<SurveyBundleFrame>& frames, const CameraModel& camera,
                                     const std::vector<Eigen::Vector3d>& points_start,
                                     const std::vector<SurveyBundleObservation>& observations,
                                     const SurveyBundleOptions& options, SurveyBundleDrift* window_drift) {
  options.Check();
  const int n_frames = static_cast<int>(frames.size()), n_points = static_cast<int>(points_start.size());
  for (size_t k = 0; k < observations.size(); ++k) {
    const auto& o = observations[k];
    if (o.frame < 0 || o.frame >= n_frames || o.point < 0 || o.point >= n_points)
      throw InputError("", 0, "observations[" + std::to_string(k) + "]", "frame or point index out of range");
  }
  for (int i = 1; i < n_frames; ++i)
    if (!(frames[i].time_s >= frames[i - 1].time_s))
      throw InputError("", 0, "time_s[" + std::to_string(i) + "]", "expected finite, non-decreasing times");

  const double sigma_n = std::max(options.nav_sigma_m, kNavSigmaFloorM);
  const double sigma_psi = std::max(options.heading_sigma_rad, kHeadingSigmaFloorRad);
  const double rho = options.nav_drift_m_per_s;

  std::vector<PoseBlock> poses(n_frames);
  for (int i = 0; i < n_frames; ++i) poses[i] = BlockFrom(frames[i].start);
  std::vector<PointBlock> points(n_points);
  for (int p = 0; p < n_points; ++p) points[p] = {points_start[p].x(), points_start[p].y(), points_start[p].z()};

  std::vector<ReprojectionResidual> reprojection;
  reprojection.reserve(observations.size());
  const Eigen::Matrix3d body_from_camera = camera.BodyFromCamera();
  for (const auto& o : observations)
    reprojection.push_back({body_from_camera, camera.mount_offset_m, (o.ideal_px.x - camera.cx) / camera.fx,
                            (o.ideal_px.y - camera.cy) / camera.fy, camera.fx / options.pixel_sigma,
                            camera.fy / options.pixel_sigma});

  SurveyBundleResult result;
  result.observation_rejected.assign(observations.size(), false);
  auto rms_px = [&]() {
    double sum = 0;
    int count = 0;
    for (size_t k = 0; k < observations.size(); ++k) {
      if (result.observation_rejected[k]) continue;
      const double e =
          ErrorPx(reprojection[k], poses[observations[k].frame], points[observations[k].point], options.pixel_sigma);
      if (!std::isfinite(e)) continue;
      sum += e * e;
      ++count;
    }
    return count ? std::sqrt(sum / count) : 0.0;
  };
  result.rms_px_before = rms_px();

  std::vector<BeamBlock> beam_planes;  // the altimeter's seabed, per beam and frame (solve_once)
  // Each altimeter reading in the last solve: its frame, its model and its first beam plane.
  struct Altimeter {
    int frame;
    BeamAltitudeResidual model;
    size_t first_plane;
  };
  std::vector<Altimeter> altimeters;
  // The navigation's drift at its knots (east, north), kept from one solve to the next.
  std::vector<std::array<double, 2>> drift;
  double knot_s = 0, knot_origin_s = n_frames > 0 ? frames[0].time_s : 0;
  int held_knots = 0;  // knots solved by an earlier window
  if (window_drift) {
    Require(window_drift->knot_s > 0 && window_drift->knots.size() >= 2 && window_drift->held_knots >= 0,
            "window_drift", "expected knots at least 2 and a positive spacing");
    knot_s = window_drift->knot_s;
    knot_origin_s = window_drift->origin_time_s;
    drift = window_drift->knots;
    held_knots = window_drift->held_knots;
  } else if (options.drift_knot_s > 0 && n_frames > 0 && !options.prior_origin_time_s) {
    // (A window of a longer survey without window_drift, prior_origin_time_s: the growing absolute prior.)
    const double span_s = frames.back().time_s - frames[0].time_s;
    knot_s = std::max(options.drift_knot_s, span_s / n_frames);  // never more knots than frames
    drift.assign(static_cast<size_t>(std::ceil(span_s / knot_s)) + 2, {0, 0});
  }
  // Each frame's knot (the one before its time), and whether its drifted
  // position prior holds anything free: a held frame between held knots does not.
  std::vector<int> frame_knot(n_frames, 0);
  std::vector<bool> frame_drift_prior(n_frames, !drift.empty());
  int first_knot = static_cast<int>(drift.size()), last_knot = -1;  // the knots in the problem
  for (int i = 0; i < n_frames && !drift.empty(); ++i) {
    const double at = (frames[i].time_s - knot_origin_s) / knot_s;
    frame_knot[i] = std::clamp(static_cast<int>(std::floor(at)), 0, static_cast<int>(drift.size()) - 2);
    frame_drift_prior[i] = !(frames[i].fixed && frame_knot[i] + 1 < held_knots);
    if (!frame_drift_prior[i]) continue;
    first_knot = std::min(first_knot, frame_knot[i]);
    last_knot = std::max(last_knot, frame_knot[i] + 1);
  }
  if (!window_drift && !drift.empty()) first_knot = 0, last_knot = static_cast<int>(drift.size()) - 1;
  auto solve_once = [&]() {
    ceres::Problem::Options problem_options;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
    ceres::Problem problem(problem_options);
    ceres::CauchyLoss reprojection_loss(options.reprojection_loss_scale);
    ceres::HuberLoss prior_loss(options.prior_loss_scale);
    ceres::HuberLoss plane_loss(options.prior_loss_scale);
    std::vector<double*> plane_blocks;
    std::vector<int> point_views(n_points, 0), frame_views(n_frames, 0);
    for (size_t k = 0; k < observations.size(); ++k) {
      // Ceres stops at once when a residual cannot be evaluated where it starts:
      // a point (a wrong match's) behind a camera is dropped first.
      if (!std::isfinite(ErrorPx(reprojection[k], poses[observations[k].frame], points[observations[k].point],
                                 options.pixel_sigma)))
        result.observation_rejected[k] = true;
      if (result.observation_rejected[k]) continue;
      ++point_views[observations[k].point];
      ++frame_views[observations[k].frame];
    }
    for (int i = 0; i < n_frames; ++i) {
      problem.AddParameterBlock(poses[i].data(), 6);
      if (!frames[i].fixed) continue;
      if (options.held_sigma_m == 0) {
        problem.SetParameterBlockConstant(poses[i].data());
        continue;
      }
      // Held where an earlier window left it, up to that window's uncertainty.
      const PoseBlock held = BlockFrom(frames[i].start);
      for (int c = 0; c < 6; ++c)
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<AbsoluteResidual, 1, 6>(new AbsoluteResidual{
                c, held[c], 1 / (c < 3 ? options.held_sigma_m : options.held_sigma_deg * kDegToRad), c >= 3}),
            nullptr, poses[i].data());
    }
    for (int p = 0; p < n_points; ++p) {
      if (point_views[p] < 2) continue;  // one ray places nothing
      problem.AddParameterBlock(points[p].data(), 3);
    }
    for (size_t k = 0; k < observations.size(); ++k) {
      const auto& o = observations[k];
      if (result.observation_rejected[k] || point_views[o.point] < 2) continue;
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<ReprojectionResidual, 2, 6, 3>(new ReprojectionResidual(reprojection[k])),
          &reprojection_loss, poses[o.frame].data(), points[o.point].data());
    }
    // The altimeter's seabed: kept points by where they are, for searches near its beams.
    const double cell_m = 0.25;
    auto cell_key = [&](double east, double north) {
      return (static_cast<int64_t>(std::floor(east / cell_m)) << 32) ^
             (static_cast<int64_t>(std::floor(north / cell_m)) & 0xffffffff);
    };
    std::unordered_map<int64_t, std::vector<int>> grid;
    for (int p = 0; p < n_points; ++p)
      if (point_views[p] >= 2) grid[cell_key(points[p][0], points[p][1])].push_back(p);
    // Up to `count` kept points nearest (east, north) within `radius`: (offset east, offset north, point).
    auto nearest = [&](double east, double north, double radius, size_t count) {
      std::vector<std::pair<double, int>> found;
      const int reach = static_cast<int>(std::ceil(radius / cell_m));
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const auto it = grid.find(cell_key(east + dx * cell_m, north + dy * cell_m));
          if (it == grid.end()) continue;
          for (int p : it->second) {
            const double d = std::hypot(points[p][0] - east, points[p][1] - north);
            if (d <= radius) found.emplace_back(d, p);
          }
        }
      const size_t k = std::min(found.size(), count);
      std::partial_sort(found.begin(), found.begin() + k, found.end());
      found.resize(k);
      return found;
    };
    // The altimeter's reading: the vehicle's height above the mean seabed height
    // where its beams land, each beam's seabed a plane block tied to the points
    // nearest its footprint by one residual each (or, with one vertical beam,
    // above the seabed at the nadir). Every residual holds at most one point.
    const int beams = options.dvl_beam_angle_deg > 0 ? 4 : 1;
    beam_planes.clear();
    altimeters.clear();
    beam_planes.reserve(static_cast<size_t>(n_frames) * beams);  // Ceres holds pointers into it
    auto AddAltitude = [&](int i, const VehiclePose& nav, const auto& near_points, ceres::Problem* to,
                           ceres::LossFunction* loss) {
      const Eigen::Matrix3d r_nb =
          NedFromBodyDeg(poses[i][3] / kDegToRad, poses[i][4] / kDegToRad, poses[i][5] / kDegToRad);
      const double tilt = options.dvl_beam_angle_deg * kDegToRad;
      const double radius = std::max(0.1, 0.15 * nav.altitude_m);
      // The planes stand in for the seabed up to its curvature over the neighbourhood.
      const double curvature_sigma_m = std::max(0.005, options.beam_plane_sigma_share * radius);
      BeamAltitudeResidual altitude{nav.altitude_m, 1 / options.altitude_sigma_m, {}, {}};
      struct Beam {
        std::vector<std::pair<double, int>> found;
        Eigen::Vector3d plane;
        bool spans;
      };
      std::vector<Beam> planned;
      for (int b = 0; b < beams; ++b) {
        const double azimuth = (45 + 90 * b) * kDegToRad;
        const Eigen::Vector3d body(std::cos(azimuth) * std::sin(tilt), std::sin(azimuth) * std::sin(tilt),
                                   std::cos(tilt));
        const Eigen::Vector3d ray = r_nb * body;
        if (!(ray.z() > 0.1)) return;
        const double east = poses[i][0] + ray.y() * nav.altitude_m / ray.z();
        const double north = poses[i][1] + ray.x() * nav.altitude_m / ray.z();
        Beam beam;
        beam.found = near_points(east, north, radius, static_cast<size_t>(options.altitude_points));
        if (beam.found.empty()) return;  // a beam on unknown ground: no reading to compare
        std::vector<Eigen::Vector2d> offsets;
        std::vector<double> heights;
        for (const auto& f : beam.found) {
          offsets.emplace_back(points[f.second][0] - east, points[f.second][1] - north);
          heights.push_back(points[f.second][2]);
        }
        beam.plane = FitPlane(offsets, heights, &beam.spans);
        altitude.beams_body.push_back(body);
        altitude.anchors.emplace_back(east, north);
        planned.push_back(std::move(beam));
      }
      {
        // A beam that grazes its plane from where the solve starts has no reading to compare.
        std::vector<BeamBlock> start_planes;
        std::vector<const double*> start_blocks = {poses[i].data()};
        for (const Beam& b : planned) start_planes.push_back({b.plane(0), b.plane(1), b.plane(2)});
        for (const BeamBlock& b : start_planes) start_blocks.push_back(b.data());
        double residual = 0;
        if (planned.empty() || !altitude(start_blocks.data(), &residual)) return;
      }
      std::vector<double*> blocks = {poses[i].data()};
      altimeters.push_back({i, altitude, beam_planes.size()});
      for (size_t b = 0; b < planned.size(); ++b) {
        beam_planes.push_back({planned[b].plane(0), planned[b].plane(1), planned[b].plane(2)});
        double* plane = beam_planes.back().data();
        to->AddParameterBlock(plane, 3);
        if (!planned[b].spans) to->SetManifold(plane, new ceres::SubsetManifold(3, {1, 2}));  // a level plane
        plane_blocks.push_back(plane);
        blocks.push_back(plane);
        for (const auto& f : planned[b].found)
          to->AddResidualBlock(new ceres::AutoDiffCostFunction<BeamPlaneResidual, 1, 3, 3>(new BeamPlaneResidual{
                                   altitude.anchors[b].x(), altitude.anchors[b].y(), 1 / curvature_sigma_m}),
                               &plane_loss, plane, points[f.second].data());
      }
      auto* cost = new ceres::DynamicAutoDiffCostFunction<BeamAltitudeResidual, 4>(
          new BeamAltitudeResidual(std::move(altitude)));
      cost->AddParameterBlock(6);
      for (size_t b = 0; b < planned.size(); ++b) cost->AddParameterBlock(3);
      cost->SetNumResiduals(1);
      to->AddResidualBlock(cost, loss, blocks);
    };
    // The navigation's drift (east, north) at knots knot_s apart from the
    // first frame's time: it starts within the noise and each step stays
    // within what the drift rate allows. A constant offset of the whole map
    // changes only the first knot's residual, so the map is held where the
    // navigation starts, not pulled along by its drift.
    // In a window of a longer survey the knots before it are held where
    // earlier windows solved them: the drift goes on across the seam.
    if (first_knot <= last_knot) {
      for (int k = first_knot; k <= last_knot; ++k) {
        problem.AddParameterBlock(drift[k].data(), 2);
        if (k < held_knots) problem.SetParameterBlockConstant(drift[k].data());
      }
      if (first_knot == 0 && held_knots == 0)
        problem.AddResidualBlock(
            new ceres::AutoDiffCostFunction<NavDriftStartResidual, 2, 2>(new NavDriftStartResidual{1 / sigma_n}),
            nullptr, drift[0].data());
      const double step_sigma_m = std::max(sigma_n, rho * knot_s);
      for (int k = first_knot; k < last_knot; ++k)
        if (k + 1 >= held_knots)
          problem.AddResidualBlock(new ceres::AutoDiffCostFunction<NavDriftStepResidual, 2, 2, 2>(
                                       new NavDriftStepResidual{1 / step_sigma_m}),
                                   nullptr, drift[k].data(), drift[k + 1].data());
    }
    for (int i = 0; i < n_frames; ++i) {
      const VehiclePose& nav = frames[i].nav;
      const double tau_s = frames[i].time_s - options.prior_origin_time_s.value_or(frames[0].time_s);
      if (!drift.empty()) {
        // The navigation's position less its drift at this time, up to its noise.
        const double at = (frames[i].time_s - knot_origin_s) / knot_s;
        const int k = frame_knot[i];
        if (frame_drift_prior[i])
          problem.AddResidualBlock(new ceres::AutoDiffCostFunction<DriftedNavPositionResidual, 2, 6, 2, 2>(
                                       new DriftedNavPositionResidual{nav.east_m, nav.north_m, at - k, 1 / sigma_n}),
                                   &prior_loss, poses[i].data(), drift[k].data(), drift[k + 1].data());
      } else {
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<NavPositionResidual, 1 * 2, 6>(new NavPositionResidual{
                                     nav.east_m, nav.north_m, 1 / std::hypot(sigma_n, rho * tau_s)}),
                                 &prior_loss, poses[i].data());
      }
      auto absolute = [&](int index, double value, double sigma, bool angle) {
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<AbsoluteResidual, 1, 6>(
                                     new AbsoluteResidual{index, value, 1 / sigma, angle}),
                                 &prior_loss, poses[i].data());
      };
      absolute(2, -nav.depth_m, options.depth_sigma_m, false);
      absolute(3, nav.heading_deg * kDegToRad, sigma_psi, true);
      absolute(4, nav.pitch_deg * kDegToRad, options.attitude_sigma_rad, true);
      absolute(5, nav.roll_deg * kDegToRad, options.attitude_sigma_rad, true);
      if (nav.altitude_m > 0) AddAltitude(i, nav, nearest, &problem, &prior_loss);
      if (i + 1 == n_frames) continue;
      const VehiclePose& next = frames[i + 1].nav;
      const double dt_s = frames[i + 1].time_s - frames[i].time_s;
      problem.AddResidualBlock(
          new ceres::AutoDiffCostFunction<NavRelativeResidual<3>, 3, 6, 6>(new NavRelativeResidual<3>{
              next.east_m - nav.east_m, next.north_m - nav.north_m, (next.heading_deg - nav.heading_deg) * kDegToRad,
              1 / std::sqrt(2 * sigma_n * sigma_n + std::pow(rho * dt_s, 2)), 1 / (std::sqrt(2.0) * sigma_psi)}),
          nullptr, poses[i].data(), poses[i + 1].data());
    }
    ceres::Solver::Options solver;
    ChooseLinearSolver(options.iterative_schur, &solver, &result.linear_solver);
    // Every point is eliminated (no residual holds two); poses and beam planes form the reduced system.
    auto ordering = std::make_shared<ceres::ParameterBlockOrdering>();
    for (int p = 0; p < n_points; ++p)
      if (point_views[p] >= 2) ordering->AddElementToGroup(points[p].data(), 0);
    for (int i = 0; i < n_frames; ++i) ordering->AddElementToGroup(poses[i].data(), 1);
    for (double* plane : plane_blocks) ordering->AddElementToGroup(plane, 1);
    for (int k = first_knot; k <= last_knot; ++k) ordering->AddElementToGroup(drift[k].data(), 1);
    solver.linear_solver_ordering = ordering;
    solver.num_threads = options.threads;
    solver.max_num_iterations = options.max_iterations;
    solver.logging_type = ceres::SILENT;
    solver.minimizer_progress_to_stdout = false;
    // Relative cost changes under 1e-6 move the poses by well under a millimetre
    // (measured: 24 iterations instead of 100, the same figures).
    solver.function_tolerance = 1e-6;
    solver.parameter_tolerance = 1e-8;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    result.points_solved = 0;
    for (int p = 0; p < n_points; ++p) result.points_solved += point_views[p] >= 2;
    result.points_eliminated =
        summary.linear_solver_ordering_used.empty() ? 0 : summary.linear_solver_ordering_used.front();
    Solved s;
    s.initial_cost = summary.initial_cost;
    s.final_cost = summary.final_cost;
    s.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
    s.converged = summary.termination_type == ceres::CONVERGENCE;
    return s;
  };

  if (!observations.empty()) {
    const Solved first = solve_once();
    result.cost_before = first.initial_cost;
    bool any_rejected = false;
    for (size_t k = 0; k < observations.size(); ++k) {
      const double e =
          ErrorPx(reprojection[k], poses[observations[k].frame], points[observations[k].point], options.pixel_sigma);
      if (!(e <= options.reject_px)) result.observation_rejected[k] = any_rejected = true;
    }
    Solved last = first;
    if (any_rejected) {
      last = solve_once();
      last.iterations += first.iterations;
    }
    result.cost_after = last.final_cost;
    result.iterations = last.iterations;
    result.converged = last.converged;
  } else {
    result.converged = true;
  }
  result.rms_px_after = rms_px();
  if (window_drift) window_drift->knots = drift;
  result.altitude_range_m.assign(n_frames, std::numeric_limits<double>::quiet_NaN());
  for (const Altimeter& a : altimeters) {
    std::vector<const double*> blocks = {poses[a.frame].data()};
    for (size_t b = 0; b < a.model.beams_body.size(); ++b) blocks.push_back(beam_planes[a.first_plane + b].data());
    double residual = 0;
    if (a.model(blocks.data(), &residual))
      result.altitude_range_m[a.frame] = a.model.altitude_m + residual / a.model.inv_sigma_m;
  }

  result.poses.resize(n_frames);
  for (int i = 0; i < n_frames; ++i) {
    VehiclePose p = frames[i].nav;
    p.east_m = poses[i][0];
    p.north_m = poses[i][1];
    p.depth_m = -poses[i][2];
    p.heading_deg = WrapAngle(poses[i][3]) / kDegToRad;
    p.pitch_deg = poses[i][4] / kDegToRad;
    p.roll_deg = poses[i][5] / kDegToRad;
    result.poses[i] = p;
  }
  // Points: kept views, and the height's sigma from the widest baseline among them:
  // sigma_z ~ z^2 sigma_px / (f b).
  std::vector<std::vector<int>> seen_by(n_points);
  for (size_t k = 0; k < observations.size(); ++k)
    if (!result.observation_rejected[k]) seen_by[observations[k].point].push_back(observations[k].frame);
  result.nav_only.assign(n_frames, true);
  result.points.resize(n_points);
  for (int p = 0; p < n_points; ++p) {
    SeabedPoint& out = result.points[p];
    out.east_north_up_m = Eigen::Vector3d(points[p][0], points[p][1], points[p][2]);
    const auto& views = seen_by[p];
    out.views = views.size() >= 2 ? static_cast<int>(views.size()) : 0;
    if (!out.views) continue;
    double baseline = 0, range = 0;
    for (size_t a = 0; a < views.size(); ++a) {
      result.nav_only[views[a]] = false;
      const PoseBlock& pa = poses[views[a]];
      range = std::max(range, pa[2] - points[p][2]);
      for (size_t b = a + 1; b < views.size(); ++b) {
        const PoseBlock& pb = poses[views[b]];
        baseline = std::max(baseline, std::hypot(std::hypot(pa[0] - pb[0], pa[1] - pb[1]), pa[2] - pb[2]));
      }
    }
    out.sigma_up_m = range * range * options.pixel_sigma / (camera.fx * std::max(baseline, 1e-3));
  }
  return result;
}

}  // namespace seamap
