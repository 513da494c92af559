#include "core/trajectory/windowed_bundle.h"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <limits>
#include <string>

#include "core/camera/frame_projector.h"
#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

constexpr double kDegToRad = M_PI / 180;

// How far a solve moved a pose from its start: east, north, depth (m),
// heading, pitch, roll (deg).
using PoseCorrection = Eigen::Matrix<double, 6, 1>;

PoseCorrection CorrectionOf(const VehiclePose& start, const VehiclePose& solved) {
  const auto turn = [](double d_deg) { return std::remainder(d_deg, 360.0); };
  PoseCorrection c;
  c << solved.east_m - start.east_m, solved.north_m - start.north_m, solved.depth_m - start.depth_m,
      turn(solved.heading_deg - start.heading_deg), turn(solved.pitch_deg - start.pitch_deg),
      turn(solved.roll_deg - start.roll_deg);
  return c;
}

void Apply(const PoseCorrection& c, VehiclePose* pose) {
  pose->east_m += c[0];
  pose->north_m += c[1];
  pose->depth_m += c[2];
  pose->heading_deg += c[3];
  pose->pitch_deg += c[4];
  pose->roll_deg += c[5];
}

// Everything solved so far, frames [0, solved_until), turned and scaled as
// one about the first frame to where the headings and the altitudes measured
// so far say on average. A window holds the lanes before it frame by frame and
// is glued to them by thousands of points, so its own headings and altitudes
// could not move them: the first lanes' turn went on through the whole survey
// and grew lane by lane (docs/BUNDLE_WINDOWS.md, "The map's turn"), and the
// scale a window took from the lanes it held went on into the next, a little
// further each time (+0.12 % by 20,000 frames, "The map's scale"). The lanes'
// headings and sizes relative to each other are the images'; the map's turn
// as a whole is the headings', its scale the altimeter's, as one bundle over
// the whole survey has them. The placed points, the drift knots and the
// frames' modelled altimeter ranges move with them.
void MoveToTheMeasurements(const std::vector<SurveyBundleFrame>& frames, int solved_until,
                           std::vector<VehiclePose>* current, std::vector<double>* range_m,
                           std::vector<Eigen::Vector3d>* point_now, const std::vector<bool>& point_placed,
                           SurveyBundleDrift* drift) {
  if (solved_until <= 0) return;
  double sum_rad = 0, mean_up_m = 0;
  std::vector<double> log_ratios;  // measured altitude over the map's range, per frame with both
  for (int i = 0; i < solved_until; ++i) {
    sum_rad += std::remainder(frames[i].nav.heading_deg - (*current)[i].heading_deg, 360.0) * kDegToRad;
    mean_up_m -= (*current)[i].depth_m / solved_until;
    const double range = (*range_m)[i], measured = frames[i].nav.altitude_m;
    if (range > 0 && measured > 0) log_ratios.push_back(std::log(measured / range));
  }
  const double turn_rad = sum_rad / solved_until;
  // The median: a reading on ground the points place badly (a beam grazing a
  // slope, a fish under the DVL) moves it by one frame, not by its size.
  const double scale = log_ratios.empty() ? 1 : std::exp(Median(log_ratios));
  if (turn_rad == 0 && scale == 1) return;
  // Clockwise by turn_rad, as headings count, and scaled, about the first
  // frame; heights about the solved frames' mean height, so that the map's
  // depths stay the depth sensor's.
  const double c = scale * std::cos(turn_rad), s = scale * std::sin(turn_rad);
  const double pivot_east = (*current)[0].east_m, pivot_north = (*current)[0].north_m;
  auto moved = [&](double east, double north) {
    const double de = east - pivot_east, dn = north - pivot_north;
    return Eigen::Vector2d(pivot_east + c * de + s * dn, pivot_north - s * de + c * dn);
  };
  if (drift) {
    // The drift is the navigation less the position: each knot moves against
    // the frame nearest its time (knots past the solved frames with the last).
    int i = 0;
    for (size_t k = 0; k < drift->knots.size(); ++k) {
      const double t = drift->origin_time_s + k * drift->knot_s;
      while (i + 1 < solved_until && frames[i + 1].time_s <= t) ++i;
      const VehiclePose& p = (*current)[i];
      const Eigen::Vector2d by = moved(p.east_m, p.north_m) - Eigen::Vector2d(p.east_m, p.north_m);
      drift->knots[k][0] -= by.x();
      drift->knots[k][1] -= by.y();
    }
  }
  for (int i = 0; i < solved_until; ++i) {
    VehiclePose& p = (*current)[i];
    const Eigen::Vector2d en = moved(p.east_m, p.north_m);
    p.east_m = en.x();
    p.north_m = en.y();
    p.depth_m = -(mean_up_m + scale * (-p.depth_m - mean_up_m));
    p.heading_deg = std::remainder(p.heading_deg + turn_rad / kDegToRad, 360.0);
    (*range_m)[i] *= scale;
  }
  for (size_t p = 0; p < point_now->size(); ++p) {
    if (!point_placed[p]) continue;
    Eigen::Vector3d& g = (*point_now)[p];
    g.head<2>() = moved(g.x(), g.y());
    g.z() = mean_up_m + scale * (g.z() - mean_up_m);
  }
}

}  // namespace

void WindowedBundleOptions::Check() const {
  if (window_frames < 0 || (window_frames > 0 && window_frames < 20))
    throw InputError("", 0, "--bundle-window", "expected 0 (one bundle) or at least 20 frames");
  if (overlap_frames < 0) throw InputError("", 0, "bundle_overlap_frames", "expected at least 0 frames");
}

SurveyBundleResult SolveWindowedBundle(const std::vector<SurveyBundleFrame>& frames, const CameraModel& camera,
                                       const std::vector<Eigen::Vector3d>& points_start,
                                       const std::vector<SurveyBundleObservation>& observations,
                                       const SurveyBundleOptions& options, const WindowedBundleOptions& window,
                                       WindowedBundleReport* report, const std::function<void(int, int)>& progress) {
  window.Check();
  options.Check();
  const int n = static_cast<int>(frames.size()), n_points = static_cast<int>(points_start.size());
  WindowedBundleReport r;
  if (window.window_frames == 0 || n <= window.window_frames) {
    // The reference: one bundle over the whole survey.
    r.windows = 1;
    r.max_window_frames = n;
    if (report) *report = r;
    SurveyBundleResult whole = SolveSurveyBundle(frames, camera, points_start, observations, options);
    if (progress) progress(1, 1);
    return whole;
  }
  std::vector<std::vector<int>> by_frame(n), by_point(n_points);
  for (size_t k = 0; k < observations.size(); ++k) {
    const auto& o = observations[k];
    if (o.frame < 0 || o.frame >= n || o.point < 0 || o.point >= n_points)
      throw InputError("", 0, "observations[" + std::to_string(k) + "]", "frame or point index out of range");
    by_frame[o.frame].push_back(static_cast<int>(k));
    by_point[o.point].push_back(static_cast<int>(k));
  }

  // Windows of window_frames kept frames; a short remainder joins the last one.
  std::vector<std::pair<int, int>> kept_ranges;
  for (int a = 0; a < n;) {
    int b = std::min(n, a + window.window_frames);
    if (n - b < window.window_frames / 2) b = n;
    kept_ranges.emplace_back(a, b);
    a = b;
  }

  SurveyBundleOptions window_options = options;
  // A window's reduced system by conjugate gradients: factoring it cost ~W^2.3 (survey_bundle.h).
  window_options.iterative_schur = true;
  // Windows share one time origin for their absolute priors.
  window_options.prior_origin_time_s = options.prior_origin_time_s.value_or(frames.front().time_s);
  // And the survey's drift knots (survey_bundle.h): a window starts from the
  // knots earlier windows solved and holds those before its first kept frame,
  // so the navigation's drift goes on across the seam. (Without them each
  // window's absolute priors would grow from the survey's start and the map
  // follow the drifted navigation.)
  SurveyBundleDrift drift;
  const bool drift_knots = options.drift_knot_s > 0;
  if (drift_knots) {
    const double span_s = frames.back().time_s - *window_options.prior_origin_time_s;
    drift.origin_time_s = *window_options.prior_origin_time_s;
    drift.knot_s = std::max(options.drift_knot_s, span_s / n);  // as the global bundle spaces them
    drift.knots.assign(static_cast<size_t>(std::ceil(std::max(0.0, span_s) / drift.knot_s)) + 2, {0, 0});
  }
  auto knot_of = [&](int i) {
    return std::clamp(static_cast<int>(std::floor((frames[i].time_s - drift.origin_time_s) / drift.knot_s)), 0,
                      static_cast<int>(drift.knots.size()) - 2);
  };
  SurveyBundleResult result;
  result.nav_only.assign(n, true);
  result.observation_rejected.assign(observations.size(), false);
  result.points.resize(n_points);
  for (int p = 0; p < n_points; ++p) result.points[p].east_north_up_m = points_start[p];
  result.converged = true;
  std::vector<VehiclePose> current(n);  // the latest solve of each frame (its start before any)
  for (int i = 0; i < n; ++i) current[i] = frames[i].start;
  std::vector<double> range_now(n, std::numeric_limits<double>::quiet_NaN());  // altimeter ranges as solved
  std::vector<Eigen::Vector3d> point_now = points_start;
  int solved_until = 0;                             // frames [0, solved_until) were solved by some window
  std::vector<bool> point_placed(n_points, false);  // placed by some window
  std::vector<int> frame_local(n, -1), point_local(n_points, -1);  // reset after each window
  std::vector<double> seam_jumps_m;
  double before_sq = 0, after_sq = 0;
  size_t rms_count = 0;

  if (progress) progress(0, static_cast<int>(kept_ranges.size()));  // the bar's rate counts from here
  for (size_t w = 0; w < kept_ranges.size(); ++w) {
    const auto [a, b] = kept_ranges[w];
    const int e = std::min(n, b + window.overlap_frames);
    // The points the window's frames observe, and every frame observing them
    // up to the window's end: the earlier ones are held where they were kept.
    std::vector<int> window_points, window_frames;
    for (int i = a; i < e; ++i)
      for (int k : by_frame[i]) {
        const int p = observations[k].point;
        if (point_local[p] >= 0) continue;
        point_local[p] = static_cast<int>(window_points.size());
        window_points.push_back(p);
      }
    auto add_frame = [&](int i) {
      if (frame_local[i] >= 0) return;
      frame_local[i] = 0;
      window_frames.push_back(i);
    };
    if (a > 0) add_frame(a - 1);  // the navigation's relative motion ties the window to the one before
    for (int i = a; i < e; ++i) add_frame(i);
    for (int p : window_points)
      for (int k : by_point[p])
        if (observations[k].frame < e) add_frame(observations[k].frame);
    std::sort(window_frames.begin(), window_frames.end());  // acquisition order, as the navigation chain needs
    // The frames no window has solved yet, and the points only they see,
    // start where the planar graph and its flat seabed put them, moved as the
    // solved frames they share points with were moved: the frames just before
    // and the earlier lanes' cross-pass partners. Unmoved, they start tens of
    // millimetres from the solved frames and points they share observations
    // with: beyond the reprojection's robust loss, whose gradient then
    // vanishes, so the window stayed where it started (the rugged 720-frame
    // survey's second window: p90 143 mm). Moved by the last solved frame's
    // correction alone, a window carried that one frame's error into the next
    // lane, and along a long survey each window started further off
    // (docs/BUNDLE_WINDOWS.md, "The start of a window's new frames").
    if (w > 0 && solved_until < e) {
      std::vector<PoseCorrection> moved(e - solved_until);
      for (int i = solved_until; i < e; ++i) {
        PoseCorrection sum = PoseCorrection::Zero();
        int shared = 0;
        for (int k : by_frame[i])
          for (int k2 : by_point[observations[k].point]) {
            const int j = observations[k2].frame;
            if (j >= solved_until || result.observation_rejected[k2]) continue;
            sum += CorrectionOf(frames[j].start, current[j]);
            ++shared;
          }
        // A frame sharing nothing with a solved one goes on as the frame before it.
        PoseCorrection& c = moved[i - solved_until];
        c = shared              ? PoseCorrection(sum / shared)
            : i == solved_until ? CorrectionOf(frames[i - 1].start, current[i - 1])
                                : moved[i - solved_until - 1];
      }
      for (int i = solved_until; i < e; ++i) Apply(moved[i - solved_until], &current[i]);
      // A point no window placed moves as the new frames that see it, on average.
      for (int p : window_points) {
        if (point_placed[p]) continue;
        PoseCorrection sum = PoseCorrection::Zero();
        int seen = 0;
        for (int k : by_point[p]) {
          const int i = observations[k].frame;
          if (i < solved_until || i >= e) continue;
          sum += moved[i - solved_until];
          ++seen;
        }
        if (seen) point_now[p] = points_start[p] + Eigen::Vector3d(sum[0], sum[1], -sum[2]) / seen;
      }
    }
    std::vector<SurveyBundleFrame> sub_frames;
    sub_frames.reserve(window_frames.size());
    for (size_t l = 0; l < window_frames.size(); ++l) {
      const int i = window_frames[l];
      frame_local[i] = static_cast<int>(l);
      SurveyBundleFrame f = frames[i];
      f.start = current[i];
      f.fixed = i < a;
      sub_frames.push_back(f);
    }
    std::vector<Eigen::Vector3d> sub_points;
    sub_points.reserve(window_points.size());
    for (int p : window_points) sub_points.push_back(point_now[p]);
    std::vector<SurveyBundleObservation> sub_observations;
    std::vector<int> global_observation;
    std::vector<Eigen::Matrix3d> camera_from_ned(window_frames.size());
    std::vector<Eigen::Vector3d> centre_ned(window_frames.size());
    for (size_t l = 0; l < window_frames.size(); ++l) {
      const VehiclePose& pose = sub_frames[l].start;
      camera_from_ned[l] = NedFromCamera(camera, pose).transpose();
      centre_ned[l] =
          Eigen::Vector3d(pose.north_m, pose.east_m, pose.depth_m) + NedFromBody(pose) * camera.mount_offset_m;
    }
    for (int p : window_points)
      for (int k : by_point[p]) {
        const auto& o = observations[k];
        if (o.frame >= e) continue;  // a later window's frame
        // Dropped by an earlier window's solve: kept out, as the global bundle keeps its rejections out of
        // its second solve. (Its point moved on without it, possibly behind this camera, where the first
        // evaluation of a new solve would fail.)
        if (result.observation_rejected[k]) continue;
        const int l = frame_local[o.frame];
        const Eigen::Vector3d& g = point_now[p];
        if (!((camera_from_ned[l] * (Eigen::Vector3d(g.y(), g.x(), -g.z()) - centre_ned[l])).z() > 1e-3)) {
          result.observation_rejected[k] = true;  // behind the camera where the window starts
          continue;
        }
        sub_observations.push_back({frame_local[o.frame], point_local[p], o.ideal_px});
        global_observation.push_back(k);
      }

    if (drift_knots) drift.held_knots = w == 0 ? 0 : knot_of(a) + 1;
    const std::clock_t solve_start = std::clock();
    const SurveyBundleResult solved = SolveSurveyBundle(sub_frames, camera, sub_points, sub_observations,
                                                        window_options, drift_knots ? &drift : nullptr);
    if (drift_knots) {
      // Knots past the window's reach start the next window where its last knot ended.
      const int last = knot_of(e - 1) + 1;
      for (size_t k = last + 1; k < drift.knots.size(); ++k) drift.knots[k] = drift.knots[last];
    }

    // The seam: how far the first kept frame moved from where the window before left it.
    if (w > 0 && window.overlap_frames > 0) {
      const VehiclePose& now = solved.poses[frame_local[a]];
      const VehiclePose& before = current[a];
      seam_jumps_m.push_back(std::sqrt(std::pow(now.east_m - before.east_m, 2) +
                                       std::pow(now.north_m - before.north_m, 2) +
                                       std::pow(now.depth_m - before.depth_m, 2)));
    }
    solved_until = e;
    for (int i = a; i < e; ++i) {
      const int l = frame_local[i];
      current[i] = solved.poses[l];
      range_now[i] = solved.altitude_range_m[l];
      if (i < b) result.nav_only[i] = solved.nav_only[l];
    }
    for (size_t l = 0; l < window_points.size(); ++l) {
      if (solved.points[l].views < 2) continue;  // a point this window could not place keeps its earlier solve
      point_placed[window_points[l]] = true;
      point_now[window_points[l]] = solved.points[l].east_north_up_m;
      result.points[window_points[l]] = solved.points[l];
    }
    MoveToTheMeasurements(frames, e, &current, &range_now, &point_now, point_placed, drift_knots ? &drift : nullptr);
    for (size_t k = 0; k < global_observation.size(); ++k)
      result.observation_rejected[global_observation[k]] = solved.observation_rejected[k];
    const size_t kept =
        static_cast<size_t>(std::count(solved.observation_rejected.begin(), solved.observation_rejected.end(), false));
    before_sq += solved.rms_px_before * solved.rms_px_before * kept;
    after_sq += solved.rms_px_after * solved.rms_px_after * kept;
    rms_count += kept;
    result.cost_before += solved.cost_before;
    result.cost_after += solved.cost_after;
    result.iterations += solved.iterations;
    result.converged = result.converged && solved.converged;
    result.linear_solver = solved.linear_solver;
    result.points_solved += solved.points_solved;
    result.points_eliminated += solved.points_eliminated;
    WindowCost cost;
    cost.first_kept_frame = a;
    cost.end_kept_frame = b;
    cost.held_frames = static_cast<int>(
        std::count_if(sub_frames.begin(), sub_frames.end(), [](const SurveyBundleFrame& f) { return f.fixed; }));
    cost.solved_frames = static_cast<int>(sub_frames.size()) - cost.held_frames;
    cost.points = static_cast<int>(sub_points.size());
    cost.observations = static_cast<int>(sub_observations.size());
    cost.iterations = solved.iterations;
    cost.start_rms_px = solved.rms_px_before;
    cost.cpu_s = static_cast<double>(std::clock() - solve_start) / CLOCKS_PER_SEC;
    r.window_costs.push_back(cost);
    r.max_window_frames = std::max(r.max_window_frames, static_cast<int>(window_frames.size()));
    ++r.windows;

    for (int i : window_frames) frame_local[i] = -1;
    for (int p : window_points) point_local[p] = -1;
    if (progress) progress(static_cast<int>(w + 1), static_cast<int>(kept_ranges.size()));
  }
  // Each frame as the window that kept it left it (held frames' later solves
  // are not kept), each placed point as its last window did, all moved since.
  result.poses = current;
  result.altitude_range_m = range_now;
  for (int p = 0; p < n_points; ++p)
    if (point_placed[p]) result.points[p].east_north_up_m = point_now[p];
  if (rms_count) {
    result.rms_px_before = std::sqrt(before_sq / rms_count);
    result.rms_px_after = std::sqrt(after_sq / rms_count);
  }
  if (!seam_jumps_m.empty()) {
    r.max_seam_jump_m = *std::max_element(seam_jumps_m.begin(), seam_jumps_m.end());
    r.median_seam_jump_m = Median(seam_jumps_m);
  }
  if (report) *report = r;
  return result;
}

}  // namespace seamap
