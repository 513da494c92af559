#include "core/trajectory/survey_refiner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <map>
#include <memory>

#include "core/camera/frame_projector.h"
#include "core/image/image_read.h"
#include "core/trajectory/ground_offsets.h"
#include "core/trajectory/match_tracks.h"
#include "core/trajectory/pair_candidates.h"
#include "core/trajectory/pose_graph.h"
#include "core/trajectory/seabed_tracks.h"
#include "core/trajectory/survey_bundle.h"
#include "core/trajectory/windowed_bundle.h"
#include "core/util/error.h"
#include "core/util/statistics.h"
#include "core/util/thread_pool.h"

namespace seamap {
namespace {

constexpr double kDegToRad = M_PI / 180;
using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

struct Prepared {
  FrameFeatures features;
  RegistrationFrame registration;
  std::string problem;
  bool ready = false;  // features detected and usable
  size_t Bytes() const { return features.Bytes() + registration.offsets.size() * sizeof(cv::Point2d); }
};

// A frame's footprint as navigated, before its image is read.
CandidateFrame Candidate(const FrameSpec& f, double time_s, const CameraModel& camera) {
  CandidateFrame c;
  c.time_s = time_s;
  const auto corners = Footprint(camera, f.pose);
  c.usable = corners.has_value();
  if (corners)
    for (int k = 0; k < 4; ++k) c.footprint[k] = {(*corners)[k].east, (*corners)[k].north};
  return c;
}

Prepared Prepare(const FrameSpec& f, const CandidateFrame& candidate, const CameraModel& camera,
                 const FeatureOptions& options, int64_t max_image_pixels) {
  Prepared p;
  if (!candidate.usable) {
    p.problem = "the camera does not see the seabed in this attitude";
    return p;
  }
  const cv::Mat image = ReadGuardedImage(f.image_path, &p.problem, max_image_pixels);
  if (image.empty()) return p;
  if (auto why = WhyNoTexture(image)) {
    p.problem = *why;
    return p;
  }
  if (std::abs(image.cols * camera.height - image.rows * camera.width) > std::max(image.cols, camera.width)) {
    p.problem =
        "image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) + ", not the camera's shape";
    return p;
  }
  p.features = DetectFeatures(image, camera, options);
  auto offsets = GroundOffsets(camera, f.pose, p.features.ideal_px);
  if (!offsets || p.features.ideal_px.size() < 20) {
    p.problem = "too few features";
    return p;
  }
  RegistrationFrame& r = p.registration;
  r.offsets = std::move(*offsets);
  r.position_m = {f.pose.east_m, f.pose.north_m};
  r.heading_rad = f.pose.heading_deg * kDegToRad;
  r.ground_px_m = GroundSampleDistance(camera, f.pose.altitude_m);
  r.k = camera.K();
  const auto& c = candidate.footprint;
  double area = 0;
  for (int k = 0; k < 4; ++k) area += c[k].x * c[(k + 1) % 4].y - c[(k + 1) % 4].x * c[k].y;
  r.footprint_m2 = std::fabs(area) / 2;
  p.ready = true;
  return p;
}

// A track's starting point for the bundle: where its rays from the start
// poses meet (least squares, then the reprojection error), not the level
// seabed below them. On relief the level start is ~10 px from its views,
// where the robust loss barely pulls, and a large survey's solve then stalls
// far from the answer (docs/TERRAIN.md, "rugged seed 2"). Rays too nearly
// parallel to place the height, or meeting beyond the reach relief allows,
// keep the level start.
Eigen::Vector3d StartPoint(const CameraModel& camera, const std::vector<RefinedFrame>& poses,
                           const std::vector<std::vector<cv::Point2f>>& keypoints_px, const MatchTrack& track,
                           const Eigen::Vector3d& level_start, double relief_share) {
  TrackOptions loose;
  loose.min_views = 2;
  loose.max_reprojection_px = std::numeric_limits<double>::infinity();  // keep every view
  loose.min_ray_angle_deg = 1;
  SeabedTrack rays;
  std::vector<TrackCamera> views;
  double reach_m = 0;
  for (const auto& [frame, keypoint] : track.views) {
    rays.observations.push_back({frame, keypoint, keypoints_px[frame][keypoint]});
    views.push_back(TrackCameraOf(camera, poses[frame].pose));
    reach_m = std::max(reach_m, std::max(0.1, relief_share * poses[frame].pose.altitude_m));
  }
  loose.max_relief_m = reach_m;
  std::string why;
  if (!TriangulateTrack(camera, views, loose, &rays, &why)) return level_start;
  return rays.east_north_up_m;
}

}  // namespace

void RefineOptions::Check() const {
  if (!(nav_noise_m >= 0) || !std::isfinite(nav_noise_m))
    throw InputError("", 0, "--nav-noise", "expected metres >= 0");
  if (!(nav_drift_m_per_min >= 0) || !std::isfinite(nav_drift_m_per_min))
    throw InputError("", 0, "--nav-drift", "expected metres per minute >= 0");
  if (!(heading_noise_deg >= 0) || !std::isfinite(heading_noise_deg))
    throw InputError("", 0, "--heading-noise", "expected degrees >= 0");
  if (max_cross_per_frame < 0) throw InputError("", 0, "max_cross_per_frame", "expected >= 0");
  if (!(relief_share >= 0 && relief_share < 1))
    throw InputError("", 0, "--relief-share", "expected a number in [0, 1)");
  if (max_points_per_frame < 1) throw InputError("", 0, "max_points_per_frame", "expected at least 1");
  if (max_views_per_point < 2) throw InputError("", 0, "max_views_per_point", "expected at least 2");
  if (!(attitude_noise_deg > 0) || !std::isfinite(attitude_noise_deg))
    throw InputError("", 0, "--attitude-noise", "expected degrees > 0");
  if (!(depth_noise_m > 0) || !std::isfinite(depth_noise_m))
    throw InputError("", 0, "--depth-noise", "expected metres > 0");
  if (!(altitude_noise_m > 0) || !std::isfinite(altitude_noise_m))
    throw InputError("", 0, "--altitude-noise", "expected metres > 0");
  if (!(pixel_sigma > 0)) throw InputError("", 0, "pixel_sigma", "expected pixels > 0");
  WindowedBundleOptions{bundle_window_frames, bundle_window_frames / 4}.Check();
  features.Check();
  registration.Check();
}

std::vector<RefinedFrame> RefineSurvey(const std::vector<FrameSpec>& frames, const CameraModel& camera,
                                       const RefineOptions& options, RefineReport* report,
                                       const std::function<void(const std::string&, int, int)>& progress,
                                       SeabedPoints* seabed_points) {
  options.Check();
  RefineReport r;
  const int n = static_cast<int>(frames.size());
  r.frames = n;
  std::vector<double> times(frames.size());
  for (size_t i = 0; i < frames.size(); ++i)
    times[i] = frames[i].time_s ? *frames[i].time_s : static_cast<double>(i) / 5;  // no times: 5 frames/s
  RefineMethod method = options.method;
  // Past ReliefChoiceOptions::max_bundle_frames one bundle is too large: it is
  // solved in windows (windowed_bundle.h) unless --bundle-window says otherwise.
  const ReliefChoiceOptions relief_choice;
  int bundle_window = options.bundle_window_frames;
  if (bundle_window == 0 && n > relief_choice.max_bundle_frames && relief_choice.max_bundle_frames > 0)
    bundle_window = relief_choice.bundle_window_frames;
  if (method == RefineMethod::kAuto) {
    const ReliefChoice choice = ChooseRefineMethod(frames, times, relief_choice);
    method = choice.method;
    r.navigated_relief_m = choice.relief_rms_m;
    if (options.bundle_window_frames == 0) r.method_note = choice.note;
  }
  const bool bundle = method == RefineMethod::kBundle;
  // Floors keep exact navigation from dividing by zero.
  const double nav_noise = std::max(options.nav_noise_m, 1e-3);
  const double drift = std::max(options.nav_drift_m_per_min, 0.0) / 60;
  const double heading_noise = std::max(options.heading_noise_deg, 0.01) * kDegToRad;
  RegistrationOptions registration = options.registration;
  if (bundle) registration.parallax_share = options.relief_share;
  ThreadPool pool(options.threads);
  auto tick = [&](const std::string& stage, int done, int total) {
    if (progress) progress(stage, done, total);
  };

  // 1. Candidate pairs, from the navigation's footprints.
  auto start = Clock::now();
  CandidateOptions candidate_options;
  candidate_options.nav_noise_m = nav_noise;
  candidate_options.drift_m_per_s = drift;
  candidate_options.min_gap_s = options.min_gap_s;
  candidate_options.min_overlap = options.min_overlap;
  candidate_options.max_cross_per_frame = options.max_cross_per_frame;
  std::vector<CandidateFrame> candidate_frames(frames.size());
  for (int i = 0; i < n; ++i) candidate_frames[i] = Candidate(frames[i], times[i], camera);
  const std::vector<CandidatePair> candidates = FindCandidatePairs(candidate_frames, candidate_options);

  // 2. Features frame by frame, and each pair registered as soon as its later
  // frame has them; a frame's features are freed after its last pair.
  std::vector<int> last_use(n);
  for (int i = 0; i < n; ++i) last_use[i] = i;
  std::vector<std::vector<int>> pairs_ending_at(n);  // candidates by their later frame
  for (size_t k = 0; k < candidates.size(); ++k) {
    const CandidatePair& c = candidates[k];
    last_use[c.i] = std::max(last_use[c.i], c.j);
    pairs_ending_at[c.j].push_back(static_cast<int>(k));
  }
  std::vector<Prepared> prepared(frames.size());
  std::vector<PairRegistration> registered(candidates.size());
  std::vector<bool> tried(candidates.size(), false);
  std::vector<std::vector<cv::Point2f>> keypoints_px(bundle ? n : 0);  // kept for the bundle's observations
  const int chunk = std::max(8, 8 * pool.size());
  size_t held_bytes = 0;
  double seconds_features = 0;
  for (int begin = 0; begin < n; begin += chunk) {
    const int end = std::min(n, begin + chunk);
    const auto features_start = Clock::now();
    {
      std::vector<std::future<Prepared>> jobs;
      for (int i = begin; i < end; ++i)
        jobs.push_back(pool.Submit([&, i] {
          return Prepare(frames[i], candidate_frames[i], camera, options.features, options.max_image_pixels);
        }));
      for (int i = begin; i < end; ++i) {
        prepared[i] = jobs[i - begin].get();
        prepared[i].registration.features = &prepared[i].features;
        if (!prepared[i].ready) ++r.frames_without_features;
        if (bundle) keypoints_px[i] = prepared[i].features.ideal_px;
        held_bytes += prepared[i].Bytes();
      }
    }
    seconds_features += Since(features_start);
    r.peak_feature_bytes = std::max(r.peak_feature_bytes, held_bytes);
    std::vector<std::pair<int, std::future<PairRegistration>>> jobs;
    for (int j = begin; j < end; ++j)
      for (int k : pairs_ending_at[j]) {
        const CandidatePair& c = candidates[k];
        if (!prepared[c.i].ready || !prepared[c.j].ready) continue;
        tried[k] = true;
        RelativeNavNoise noise;
        noise.position_m = RelativeSigma(nav_noise, drift, std::fabs(times[c.j] - times[c.i]));
        noise.heading_rad = std::sqrt(2.0) * heading_noise;
        jobs.emplace_back(k, pool.Submit([&, c, noise] {
          return RegisterPair(prepared[c.i].registration, prepared[c.j].registration, noise, registration,
                              static_cast<uint64_t>(c.i) * 7919 + c.j);
        }));
      }
    for (auto& [k, job] : jobs) {
      registered[k] = job.get();
      if (!bundle) registered[k].inlier_matches.clear();
    }
    for (int i = 0; i < end; ++i)
      if (last_use[i] < end && prepared[i].registration.features) {
        held_bytes -= prepared[i].Bytes();
        prepared[i].features = FrameFeatures();
        prepared[i].registration.offsets = std::vector<cv::Point2d>();
        prepared[i].registration.features = nullptr;
      }
    tick("features", end, n);
  }
  r.seconds_features = seconds_features;

  std::vector<PairConstraint> constraints;
  std::vector<int> constraint_candidate;
  std::vector<double> inliers;
  std::map<std::string, int> failures;
  std::vector<bool> still_photos(frames.size(), false);
  for (size_t k = 0; k < candidates.size(); ++k) {
    if (!tried[k]) continue;
    (candidates[k].along_track ? r.pairs_along : r.pairs_cross)++;
    const PairRegistration& g = registered[k];
    if (!g.accepted) {
      ++failures[g.reason.substr(0, g.reason.find(" ("))];
      if (g.reason.rfind("identical frames", 0) == 0 || g.reason.rfind("no parallax", 0) == 0)
        still_photos[candidates[k].i] = still_photos[candidates[k].j] = true;
      continue;
    }
    (candidates[k].along_track ? r.registered_along : r.registered_cross)++;
    PairConstraint c;
    c.i = candidates[k].i;
    c.j = candidates[k].j;
    c.dt_east_m = g.dt_east_m;
    c.dt_north_m = g.dt_north_m;
    c.dheading_rad = g.dheading_rad;
    c.covariance = g.covariance;
    c.along_track = candidates[k].along_track;
    constraints.push_back(c);
    constraint_candidate.push_back(static_cast<int>(k));
    inliers.push_back(g.inliers);
  }
  for (const auto& f : failures) r.failures.push_back(f);
  r.median_inliers = Median(inliers);
  r.seconds_pairs = Since(start) - seconds_features;

  // 3. The planar pose graph: the answer on a flat seabed, the bundle's start on relief.
  start = Clock::now();
  std::vector<PlanarPose> nav(frames.size());
  for (size_t i = 0; i < frames.size(); ++i)
    nav[i] = {frames[i].pose.east_m, frames[i].pose.north_m, frames[i].pose.heading_deg * kDegToRad};
  PoseGraphOptions graph;
  graph.nav_sigma_m = nav_noise;
  graph.nav_drift_m_per_s = drift;
  graph.heading_sigma_rad = heading_noise;
  graph.threads = pool.size();
  const PoseGraphResult solved = SolvePoseGraph(nav, times, constraints, graph);
  r.seconds_solve = Since(start);
  tick("solve", 1, 1);

  const PairResidualRms residuals = PairResiduals(constraints, nav, solved);
  r.rejected_by_graph += residuals.rejected;
  r.residual_before_mm = residuals.before_mm;
  r.residual_after_mm = residuals.after_mm;
  std::vector<RefinedFrame> out(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    out[i].pose = frames[i].pose;
    out[i].pose.east_m = solved.poses[i].east_m;
    out[i].pose.north_m = solved.poses[i].north_m;
    out[i].pose.heading_deg = solved.poses[i].heading_rad / kDegToRad;
    out[i].nav_only = solved.nav_only[i];
    out[i].still_photos = still_photos[i];
    out[i].problem = prepared[i].problem;
  }

  // 4. The bundle adjustment, from the planar graph's poses.
  if (bundle) {
    start = Clock::now();
    std::vector<PairMatches> matches;
    // The along-track pairs the planar graph dropped too: its rigid model of
    // the seabed is what fails over relief (pairs across slopes), not their
    // matches, which one camera motion verified, with the navigation's
    // short-term motion as a guide. Without them the bundle's map fell apart
    // into blocks joined only by the drifting navigation (docs/TERRAIN.md).
    // Cross-line pairs the graph dropped stay out: found with wide searches,
    // some are wrong, and a wrong pair joins unrelated tracks.
    for (size_t k = 0; k < constraints.size(); ++k) {
      if (solved.pair_rejected[k] && !constraints[k].along_track) continue;
      PairRegistration& g = registered[constraint_candidate[k]];
      matches.push_back({constraints[k].i, constraints[k].j, std::move(g.inlier_matches)});
    }
    registered.clear();
    registered.shrink_to_fit();
    const std::vector<MatchTrack> tracks =
        BuildTracks(matches, options.max_points_per_frame, options.max_views_per_point);
    matches.clear();
    std::vector<SurveyBundleFrame> bundle_frames(n);
    for (int i = 0; i < n; ++i) bundle_frames[i] = {frames[i].pose, out[i].pose, times[i]};
    std::vector<Eigen::Vector3d> points_start;
    std::vector<SurveyBundleObservation> observations;
    int tracks_spread = 0;
    for (const MatchTrack& t : tracks) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      std::vector<std::pair<Eigen::Vector3d, double>> flat;  // on the level seabed, with the reach relief allows
      for (const auto& [frame, keypoint] : t.views)
        if (const auto g = FlatSeabedPoint(camera, out[frame].pose, keypoints_px[frame][keypoint])) {
          sum += *g;
          flat.emplace_back(*g, std::max(0.1, options.relief_share * out[frame].pose.altitude_m));
        }
      if (flat.empty()) continue;
      // Views of one seabed point land on the level seabed within the parallax
      // relief allows; further apart, a wrong match joined two tracks.
      const Eigen::Vector3d mean = sum / static_cast<double>(flat.size());
      bool spread = false;
      for (const auto& [g, reach] : flat) spread |= (g - mean).head<2>().norm() > reach;
      if (spread) {
        ++tracks_spread;
        continue;
      }
      const int point = static_cast<int>(points_start.size());
      points_start.push_back(
          StartPoint(camera, out, keypoints_px, t, sum / static_cast<double>(flat.size()), options.relief_share));
      for (const auto& [frame, keypoint] : t.views)
        observations.push_back({frame, point, keypoints_px[frame][keypoint]});
    }
    keypoints_px.clear();
    keypoints_px.shrink_to_fit();
    SurveyBundleOptions b;
    b.nav_sigma_m = nav_noise;
    b.nav_drift_m_per_s = drift;
    b.heading_sigma_rad = heading_noise;
    b.attitude_sigma_rad = options.attitude_noise_deg * kDegToRad;
    b.depth_sigma_m = options.depth_noise_m;
    b.altitude_sigma_m = options.altitude_noise_m;
    b.pixel_sigma = options.pixel_sigma;
    b.threads = pool.size();
    WindowedBundleReport windows;
    const SurveyBundleResult adjusted =
        SolveWindowedBundle(bundle_frames, camera, points_start, observations, b, {bundle_window, bundle_window / 4},
                            &windows, [&](int done, int total) { tick("bundle", done, total); });
    r.bundle_windows = windows.windows;
    r.bundle_seam_jump_max_mm = 1000 * windows.max_seam_jump_m;
    r.bundle_seam_jump_median_mm = 1000 * windows.median_seam_jump_m;
    std::vector<double> window_cpu_s;
    for (const WindowCost& c : windows.window_costs) {
      r.bundle_window_solved_frames_max = std::max(r.bundle_window_solved_frames_max, c.solved_frames);
      r.bundle_window_held_frames_max = std::max(r.bundle_window_held_frames_max, c.held_frames);
      r.bundle_window_cpu_s_max = std::max(r.bundle_window_cpu_s_max, c.cpu_s);
      r.bundle_window_start_rms_px_max = std::max(r.bundle_window_start_rms_px_max, c.start_rms_px);
      window_cpu_s.push_back(c.cpu_s);
    }
    if (!window_cpu_s.empty()) r.bundle_window_cpu_s_median = Median(window_cpu_s);
    r.bundle = true;
    r.points = static_cast<int>(points_start.size());
    r.tracks_spread = tracks_spread;
    r.observations = static_cast<int>(observations.size());
    for (bool rejected : adjusted.observation_rejected) r.observations_rejected += rejected;
    r.reprojection_before_px = adjusted.rms_px_before;
    r.reprojection_after_px = adjusted.rms_px_after;
    r.bundle_solver = adjusted.linear_solver;
    r.bundle_iterations = adjusted.iterations;
    // Every frame: one without points of its own follows its neighbours by the navigation's relative motion.
    for (int i = 0; i < n; ++i) {
      const VehiclePose& p = adjusted.poses[i];
      out[i].pose.east_m = p.east_m;
      out[i].pose.north_m = p.north_m;
      out[i].pose.depth_m = p.depth_m;
      out[i].pose.heading_deg = p.heading_deg;
      out[i].pose.pitch_deg = p.pitch_deg;
      out[i].pose.roll_deg = p.roll_deg;
    }
    if (seabed_points) {
      seabed_points->clear();
      for (const SeabedPoint& p : adjusted.points)
        if (p.views >= 2) seabed_points->push_back(p);
    }
    r.seconds_bundle = Since(start);
  }
  for (const RefinedFrame& f : out) r.nav_only += f.nav_only;
  if (report) *report = r;
  return out;
}

}  // namespace seamap
