#include "core/trajectory/survey_refiner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <map>
#include <memory>

#include "core/camera/frame_projector.h"
#include "core/image/image_read.h"
#include "core/trajectory/ground_offsets.h"
#include "core/trajectory/pair_candidates.h"
#include "core/trajectory/pose_graph.h"
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
  CandidateFrame candidate;
  std::string problem;
};

Prepared Prepare(const FrameSpec& f, double time_s, const CameraModel& camera, const FeatureOptions& options) {
  Prepared p;
  p.candidate.time_s = time_s;
  p.candidate.usable = false;
  const auto corners = Footprint(camera, f.pose);
  if (!corners) {
    p.problem = "the camera does not see the seabed in this attitude";
    return p;
  }
  for (int k = 0; k < 4; ++k) p.candidate.footprint[k] = {(*corners)[k].east, (*corners)[k].north};
  const cv::Mat image = ReadGuardedImage(f.image_path, &p.problem);
  if (image.empty()) return p;
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
  const auto& c = p.candidate.footprint;
  double area = 0;
  for (int k = 0; k < 4; ++k) area += c[k].x * c[(k + 1) % 4].y - c[(k + 1) % 4].x * c[k].y;
  r.footprint_m2 = std::fabs(area) / 2;
  p.candidate.usable = true;
  return p;
}

// How far the measured motion of a pair is from what the poses say, metres.
double Disagreement(const PairConstraint& c, const PlanarPose& a, const PlanarPose& b) {
  const cv::Point2d predicted = RotateClockwise({b.east_m - a.east_m, b.north_m - a.north_m}, -a.heading_rad);
  return std::hypot(predicted.x - c.dt_east_m, predicted.y - c.dt_north_m);
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
  features.Check();
  registration.Check();
}

std::vector<RefinedFrame> RefineSurvey(const std::vector<FrameSpec>& frames, const CameraModel& camera,
                                       const RefineOptions& options, RefineReport* report,
                                       const std::function<void(const std::string&, int, int)>& progress) {
  options.Check();
  RefineReport r;
  r.frames = static_cast<int>(frames.size());
  // Floors keep exact navigation from dividing by zero.
  const double nav_noise = std::max(options.nav_noise_m, 1e-3);
  const double drift = std::max(options.nav_drift_m_per_min, 0.0) / 60;
  const double heading_noise = std::max(options.heading_noise_deg, 0.01) * kDegToRad;
  std::vector<double> times(frames.size());
  for (size_t i = 0; i < frames.size(); ++i)
    times[i] = frames[i].time_s ? *frames[i].time_s : static_cast<double>(i) / 5;  // no times: 5 frames/s
  ThreadPool pool(options.threads);
  auto tick = [&](const std::string& stage, int done, int total) {
    if (progress) progress(stage, done, total);
  };

  // 1. Features, on the pool.
  auto start = Clock::now();
  std::vector<Prepared> prepared(frames.size());
  {
    std::vector<std::future<Prepared>> jobs;
    for (size_t i = 0; i < frames.size(); ++i)
      jobs.push_back(pool.Submit([&, i] { return Prepare(frames[i], times[i], camera, options.features); }));
    for (size_t i = 0; i < jobs.size(); ++i) {
      prepared[i] = jobs[i].get();
      prepared[i].registration.features = &prepared[i].features;
      if (!prepared[i].candidate.usable) ++r.frames_without_features;
      tick("features", static_cast<int>(i + 1), static_cast<int>(frames.size()));
    }
  }
  r.seconds_features = Since(start);

  // 2. Candidate pairs, registered on the pool.
  start = Clock::now();
  CandidateOptions candidate_options;
  candidate_options.nav_noise_m = nav_noise;
  candidate_options.drift_m_per_s = drift;
  candidate_options.min_gap_s = options.min_gap_s;
  candidate_options.min_overlap = options.min_overlap;
  candidate_options.max_cross_per_frame = options.max_cross_per_frame;
  std::vector<CandidateFrame> candidate_frames;
  for (const Prepared& p : prepared) candidate_frames.push_back(p.candidate);
  const std::vector<CandidatePair> candidates = FindCandidatePairs(candidate_frames, candidate_options);
  std::vector<std::future<Registration>> jobs;
  for (const CandidatePair& c : candidates) {
    (c.along_track ? r.pairs_along : r.pairs_cross)++;
    RelativeNavNoise noise;
    noise.position_m = RelativeSigma(nav_noise, drift, std::fabs(times[c.j] - times[c.i]));
    noise.heading_rad = std::sqrt(2.0) * heading_noise;
    jobs.push_back(pool.Submit([&, c, noise] {
      return RegisterPair(prepared[c.i].registration, prepared[c.j].registration, noise, options.registration,
                          static_cast<uint64_t>(c.i) * 7919 + c.j);
    }));
  }
  std::vector<PairConstraint> constraints;
  std::vector<double> inliers;
  std::map<std::string, int> failures;
  for (size_t k = 0; k < jobs.size(); ++k) {
    const Registration g = jobs[k].get();
    tick("pairs", static_cast<int>(k + 1), static_cast<int>(jobs.size()));
    if (!g.accepted) {
      ++failures[g.reason.substr(0, g.reason.find(" ("))];
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
    inliers.push_back(g.inliers);
  }
  for (const auto& f : failures) r.failures.push_back(f);
  r.median_inliers = Median(inliers);
  r.seconds_pairs = Since(start);

  // 3. The pose graph.
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

  double before = 0, after = 0;
  int kept = 0;
  for (size_t k = 0; k < constraints.size(); ++k) {
    if (solved.pair_rejected[k]) {
      ++r.rejected_by_graph;
      continue;
    }
    const PairConstraint& c = constraints[k];
    before += std::pow(Disagreement(c, nav[c.i], nav[c.j]), 2);
    after += std::pow(Disagreement(c, solved.poses[c.i], solved.poses[c.j]), 2);
    ++kept;
  }
  if (kept) {
    r.residual_before_mm = 1000 * std::sqrt(before / kept);
    r.residual_after_mm = 1000 * std::sqrt(after / kept);
  }
  std::vector<RefinedFrame> out(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    out[i].pose = frames[i].pose;
    out[i].pose.east_m = solved.poses[i].east_m;
    out[i].pose.north_m = solved.poses[i].north_m;
    out[i].pose.heading_deg = solved.poses[i].heading_rad / kDegToRad;
    out[i].nav_only = solved.nav_only[i];
    out[i].problem = prepared[i].problem;
    r.nav_only += out[i].nav_only;
  }
  if (report) *report = r;
  return out;
}

}  // namespace seamap
