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
  bool freed = false;  // ready once; its features freed (Bound), prepared again when a pair needs them
  size_t Bytes() const { return features.Bytes() + registration.offsets.size() * sizeof(cv::Point2d); }
};

IncrementalRefiner::IncrementalRefiner(const CameraModel& camera, const RefineOptions& options, FeatureBound bound)
    : camera_(camera),
      options_(options),
      // The floors RefineSurvey puts under the stated noise.
      nav_noise_m_(std::max(options.nav_noise_m, 1e-3)),
      drift_m_per_s_(std::max(options.nav_drift_m_per_min, 0.0) / 60),
      heading_noise_rad_(std::max(options.heading_noise_deg, 0.01) * kDegToRad),
      pool_(std::make_unique<ThreadPool>(options.threads)),
      bound_(bound) {
  options_.Check();
}

IncrementalRefiner::~IncrementalRefiner() = default;

std::unique_ptr<IncrementalRefiner::Prepared> IncrementalRefiner::Prepare(int i) const {
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
}

void IncrementalRefiner::Keep(int i, std::unique_ptr<Prepared> p) {
  p->registration.features = &p->features;  // it lives on the heap: the pointer stays valid
  feature_bytes_ += p->Bytes();
  peak_feature_bytes_ = std::max(peak_feature_bytes_, feature_bytes_);
  if (i == static_cast<int>(prepared_.size()))
    prepared_.push_back(std::move(p));
  else
    prepared_[i] = std::move(p);
}

void IncrementalRefiner::Free(int i) {
  Prepared& p = *prepared_[i];
  if (!p.ready || p.freed) return;
  feature_bytes_ -= p.Bytes();
  p.features = FrameFeatures{};
  std::vector<cv::Point2d>().swap(p.registration.offsets);  // its memory too, not only its size
  p.freed = true;
  ++features_freed_;
}

void IncrementalRefiner::FreeFeatures() {
  for (size_t i = 0; i < prepared_.size(); ++i) Free(static_cast<int>(i));
}

void IncrementalRefiner::Bound() {
  if (bound_.max_bytes == 0 || feature_bytes_ <= bound_.max_bytes) return;
  // Frames a candidate pair still waits on keep their features.
  std::vector<bool> waited(frames_.size(), false);
  for (const CandidatePair& c : candidates_)
    if (!tried_.count({c.i, c.j})) waited[c.i] = waited[c.j] = true;
  // The last frames are where the next pairs come from: never freed.
  const int n = static_cast<int>(frames_.size());
  const FrameSpec& last = frames_.back();
  std::vector<std::pair<double, int>> candidates;  // (distance from the latest position, frame)
  for (int i = 0; i < n - bound_.recent_frames; ++i)
    if (prepared_[i]->ready && !prepared_[i]->freed && !waited[i])
      candidates.emplace_back(
          std::hypot(frames_[i].pose.east_m - last.pose.east_m, frames_[i].pose.north_m - last.pose.north_m), i);
  std::sort(candidates.begin(), candidates.end(), std::greater<>());
  // Down to 80 % of the bound, so that freeing comes in batches, not a frame each Add.
  const size_t target = bound_.max_bytes / 5 * 4;
  for (const auto& [distance, i] : candidates) {
    if (feature_bytes_ <= target) break;
    Free(i);
  }
}

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
    jobs.push_back(pool_->Submit([this, i] { return Prepare(i); }));
  for (size_t k = 0; k < jobs.size(); ++k) Keep(first + static_cast<int>(k), jobs[k].get());

  // The candidates among every frame so far; those not registered yet, now.
  CandidateOptions candidate_options;
  candidate_options.nav_noise_m = nav_noise_m_;
  candidate_options.drift_m_per_s = drift_m_per_s_;
  candidate_options.min_gap_s = options_.min_gap_s;
  candidate_options.min_overlap = options_.min_overlap;
  candidate_options.max_cross_per_frame = options_.max_cross_per_frame;
  candidates_ = FindCandidatePairs(candidate_frames_, candidate_options);
  // Frames whose features were freed, in a pair not registered yet: extracted again (the same features).
  std::vector<int> again;
  for (const CandidatePair& c : candidates_)
    if (!tried_.count({c.i, c.j}))
      for (int i : {c.i, c.j})
        if (prepared_[i]->freed) again.push_back(i);
  std::sort(again.begin(), again.end());
  again.erase(std::unique(again.begin(), again.end()), again.end());
  jobs.clear();
  for (int i : again) jobs.push_back(pool_->Submit([this, i] { return Prepare(i); }));
  for (size_t k = 0; k < jobs.size(); ++k) Keep(again[k], jobs[k].get());
  features_again_ += static_cast<int>(again.size());
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
  Bound();
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
