#include "core/trajectory/incremental_refiner.h"

#include <algorithm>
#include <cmath>
#include <future>

#include "core/camera/frame_projector.h"
#include "core/image/image_read.h"
#include "core/trajectory/ground_offsets.h"
#include "core/trajectory/pair_registration.h"

namespace seamap {
namespace {

constexpr double kDegToRad = M_PI / 180;

}  // namespace

// A frame as registration needs it (RefineSurvey prepares frames the same way).
struct IncrementalRefiner::Prepared {
  FrameFeatures features;
  RegistrationFrame registration;
  bool ready = false;
};

IncrementalRefiner::IncrementalRefiner(const CameraModel& camera, const RefineOptions& options)
    : camera_(camera),
      options_(options),
      // The floors RefineSurvey puts under the stated noise.
      nav_noise_m_(std::max(options.nav_noise_m, 1e-3)),
      drift_m_per_s_(std::max(options.nav_drift_m_per_min, 0.0) / 60),
      heading_noise_rad_(std::max(options.heading_noise_deg, 0.01) * kDegToRad),
      pool_(std::make_unique<ThreadPool>(options.threads)) {
  options_.Check();
}

IncrementalRefiner::~IncrementalRefiner() = default;

int IncrementalRefiner::Add(const std::vector<FrameSpec>& frames) {
  const int first = static_cast<int>(frames_.size());
  for (const FrameSpec& f : frames) {
    const int i = static_cast<int>(frames_.size());
    frames_.push_back(f);
    times_.push_back(f.time_s ? *f.time_s : static_cast<double>(i) / 5);  // no times: 5 frames/s, as RefineSurvey
    CandidateFrame c;
    c.time_s = times_.back();
    const auto corners = Footprint(camera_, f.pose);
    c.usable = corners.has_value();
    if (corners)
      for (int k = 0; k < 4; ++k) c.footprint[k] = {(*corners)[k].east, (*corners)[k].north};
    candidate_frames_.push_back(c);
  }
  // Features of the new frames, on the pool.
  std::vector<std::future<std::unique_ptr<Prepared>>> jobs;
  for (int i = first; i < static_cast<int>(frames_.size()); ++i)
    jobs.push_back(pool_->Submit([this, i] {
      auto p = std::make_unique<Prepared>();
      const FrameSpec& f = frames_[i];
      if (!candidate_frames_[i].usable) return p;
      std::string problem;
      const cv::Mat image = ReadGuardedImage(f.image_path, &problem, options_.max_image_pixels);
      if (image.empty() || WhyNoTexture(image)) return p;
      if (std::abs(image.cols * camera_.height - image.rows * camera_.width) > std::max(image.cols, camera_.width))
        return p;
      p->features = DetectFeatures(image, camera_, options_.features);
      auto offsets = GroundOffsets(camera_, f.pose, p->features.ideal_px);
      if (!offsets || p->features.ideal_px.size() < 20) return p;
      RegistrationFrame& r = p->registration;
      r.offsets = std::move(*offsets);
      r.position_m = {f.pose.east_m, f.pose.north_m};
      r.heading_rad = f.pose.heading_deg * kDegToRad;
      r.ground_px_m = GroundSampleDistance(camera_, f.pose.altitude_m);
      r.k = camera_.K();
      const auto& c = candidate_frames_[i].footprint;
      double area = 0;
      for (int k = 0; k < 4; ++k) area += c[k].x * c[(k + 1) % 4].y - c[(k + 1) % 4].x * c[k].y;
      r.footprint_m2 = std::fabs(area) / 2;
      p->ready = true;
      return p;
    }));
  for (auto& job : jobs) {
    prepared_.push_back(job.get());
    Prepared& p = *prepared_.back();
    p.registration.features = &p.features;
    feature_bytes_ += p.features.Bytes() + p.registration.offsets.size() * sizeof(cv::Point2d);
  }

  // The candidates among every frame so far; those not registered yet, now.
  CandidateOptions candidate_options;
  candidate_options.nav_noise_m = nav_noise_m_;
  candidate_options.drift_m_per_s = drift_m_per_s_;
  candidate_options.min_gap_s = options_.min_gap_s;
  candidate_options.min_overlap = options_.min_overlap;
  candidate_options.max_cross_per_frame = options_.max_cross_per_frame;
  candidates_ = FindCandidatePairs(candidate_frames_, candidate_options);
  std::vector<std::pair<CandidatePair, std::future<PairRegistration>>> registrations;
  for (const CandidatePair& c : candidates_) {
    if (tried_.count({c.i, c.j}) || !prepared_[c.i]->ready || !prepared_[c.j]->ready) continue;
    RelativeNavNoise noise;
    noise.position_m = RelativeSigma(nav_noise_m_, drift_m_per_s_, std::fabs(times_[c.j] - times_[c.i]));
    noise.heading_rad = std::sqrt(2.0) * heading_noise_rad_;
    registrations.emplace_back(c, pool_->Submit([this, c, noise] {
      return RegisterPair(prepared_[c.i]->registration, prepared_[c.j]->registration, noise, options_.registration,
                          static_cast<uint64_t>(c.i) * 7919 + c.j);
    }));
  }
  int new_cross = 0;
  for (auto& [c, job] : registrations) {
    const PairRegistration g = job.get();
    tried_[{c.i, c.j}] = g.accepted;
    if (!g.accepted) continue;
    PairConstraint k;
    k.i = c.i;
    k.j = c.j;
    k.dt_east_m = g.dt_east_m;
    k.dt_north_m = g.dt_north_m;
    k.dheading_rad = g.dheading_rad;
    k.covariance = g.covariance;
    k.along_track = c.along_track;
    accepted_[{c.i, c.j}] = k;
    new_cross += !c.along_track;
  }
  return new_cross;
}

IncrementalSolution IncrementalRefiner::Solve() const {
  IncrementalSolution s;
  s.frames = frames();
  std::vector<PairConstraint> constraints;  // in the candidates' order, as RefineSurvey gives them
  for (const CandidatePair& c : candidates_) {
    auto it = accepted_.find({c.i, c.j});
    if (it == accepted_.end()) continue;
    PairConstraint k = it->second;
    k.along_track = c.along_track;
    constraints.push_back(k);
    (c.along_track ? s.registered_along : s.registered_cross)++;
  }
  std::vector<PlanarPose> nav(frames_.size());
  for (size_t i = 0; i < frames_.size(); ++i)
    nav[i] = {frames_[i].pose.east_m, frames_[i].pose.north_m, frames_[i].pose.heading_deg * kDegToRad};
  if (nav.empty()) return s;
  PoseGraphOptions graph;
  graph.nav_sigma_m = nav_noise_m_;
  graph.nav_drift_m_per_s = drift_m_per_s_;
  graph.heading_sigma_rad = heading_noise_rad_;
  graph.threads = pool_->size();
  PoseGraphResult solved = SolvePoseGraph(nav, times_, constraints, graph);
  const PairResidualRms residuals = PairResiduals(constraints, nav, solved);
  s.rejected_by_graph += residuals.rejected;
  s.residual_before_mm = residuals.before_mm;
  s.residual_after_mm = residuals.after_mm;
  s.poses = std::move(solved.poses);
  s.nav_only = std::move(solved.nav_only);
  return s;
}

}  // namespace seamap
