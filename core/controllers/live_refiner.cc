#include "core/controllers/live_refiner.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/camera/frame_projector.h"
#include "core/util/error.h"

namespace seamap {
namespace {

constexpr double kRadToDeg = 180 / M_PI;

// How far a frame's footprint moves between two poses: its corners' largest shift, metres.
double FootprintShift(const CameraModel& camera, const VehiclePose& a, const VehiclePose& b) {
  const auto ca = Footprint(camera, a), cb = Footprint(camera, b);
  if (!ca || !cb) return std::hypot(a.east_m - b.east_m, a.north_m - b.north_m);
  double worst = 0;
  for (int k = 0; k < 4; ++k)
    worst = std::max(worst, std::hypot((*ca)[k].east - (*cb)[k].east, (*ca)[k].north - (*cb)[k].north));
  return worst;
}

bool Moved(const VehiclePose& a, const VehiclePose& b) {
  return a.east_m != b.east_m || a.north_m != b.north_m || a.heading_deg != b.heading_deg;
}

}  // namespace

void LiveRefinerOptions::Check() const {
  refine.Check();
  if (!(base_pixel_m > 0) || !std::isfinite(base_pixel_m))
    throw InputError("", 0, "base_pixel_m", "expected metres > 0");
  if (!(repaint_threshold_px >= 0) || !std::isfinite(repaint_threshold_px))
    throw InputError("", 0, "repaint_threshold_px", "expected pixels >= 0");
  if (min_frames_between_solves < 1) throw InputError("", 0, "min_frames_between_solves", "expected at least 1");
  if (!(repaint_share > 0)) throw InputError("", 0, "repaint_share", "expected > 0");
  if (max_batch_frames < 1) throw InputError("", 0, "max_batch_frames", "expected at least 1");
}

LiveRefiner::LiveRefiner(const CameraModel& camera, LiveRefinerOptions options, Corrected corrected)
    : camera_(camera),
      options_((options.Check(), std::move(options))),
      corrected_(std::move(corrected)),
      refiner_(camera_, options_.refine, FeatureBound{options_.max_feature_bytes}),
      worker_([this] { Work(); }) {}

LiveRefiner::~LiveRefiner() {
  Stop();
}

void LiveRefiner::Add(const FrameSpec& nav, const VehiclePose& painted) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.emplace_back(nav, Clock::now());
  painted_in_.push_back(painted);
  wake_.notify_one();
}

void LiveRefiner::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
    wake_.notify_one();
  }
  if (worker_.joinable()) worker_.join();
  refiner_.FreeFeatures();  // the final solve extracts its own: the worker's are not kept beside them
}

LiveRefinerLag LiveRefiner::Lag() const {
  std::lock_guard<std::mutex> lock(mutex_);
  LiveRefinerLag lag = lag_;
  lag.frames_behind = static_cast<int>(pending_.size()) + lag_.frames_behind;
  if (stop_) return lag;  // no frames come any more: what is left goes to the final solve
  if (lag_.frames_behind > 0 || !pending_.empty()) {
    const Clock::time_point oldest = lag_.frames_behind > 0 ? batch_since_ : pending_.front().second;
    lag.seconds_behind = std::chrono::duration<double>(Clock::now() - oldest).count();
  }
  lag.worst_seconds = std::max(lag.worst_seconds, lag.seconds_behind);
  return lag;
}

void LiveRefiner::Work() {
  for (;;) {
    std::vector<FrameSpec> batch;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || !pending_.empty(); });
      if (stop_) return;
      batch_since_ = pending_.front().second;
      const size_t take = std::min(pending_.size(), static_cast<size_t>(options_.max_batch_frames));
      for (size_t k = 0; k < take; ++k) {
        batch.push_back(std::move(pending_[k].first));
        painted_.push_back(painted_in_[k]);
      }
      pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(take));
      painted_in_.erase(painted_in_.begin(), painted_in_.begin() + static_cast<std::ptrdiff_t>(take));
      lag_.frames_behind = static_cast<int>(batch.size());  // being refined
    }
    try {
      const int cross = refiner_.Add(batch);
      frames_since_solve_ += static_cast<int>(batch.size());
      cross_since_solve_ += cross;
      {
        std::lock_guard<std::mutex> lock(mutex_);
        lag_.cross_pairs += cross;
        lag_.peak_feature_mb = static_cast<double>(refiner_.peak_feature_bytes()) / (1 << 20);
        lag_.features_freed = refiner_.features_freed();
        lag_.features_again = refiner_.features_again();
      }
      if (cross_since_solve_ > 0 && frames_since_solve_ >= options_.min_frames_between_solves) SolveAndHandBack();
    } catch (const std::exception& e) {  // e.g. the disk is full: frames go on being painted; the final solve follows
      std::fprintf(stderr, "\nrefine live: stopped refining as frames come: %s\n", e.what());
      std::lock_guard<std::mutex> lock(mutex_);
      lag_.frames_behind = 0;
      lag_.failed = true;
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    // The batch is refined (and its corrections painted): how late that came.
    if (!stop_)
      lag_.worst_seconds =
          std::max(lag_.worst_seconds, std::chrono::duration<double>(Clock::now() - batch_since_).count());
    lag_.frames_behind = 0;
  }
}

void LiveRefiner::SolveAndHandBack() {
  LiveCorrection correction;
  IncrementalSolution& solution = correction.solution;
  solution = refiner_.Solve();
  const int budget = std::max(1, static_cast<int>(std::ceil(options_.repaint_share * frames_since_solve_)));
  frames_since_solve_ = cross_since_solve_ = 0;
  // Every frame refined so far at its corrected pose (the navigation's own
  // where it is exactly that), the navigation's beside it.
  const std::vector<FrameSpec>& nav = refiner_.frame_specs();
  std::vector<FrameSpec>& placed = correction.placed;
  placed.assign(nav.begin(), nav.begin() + solution.frames);
  std::vector<std::pair<double, int>> moved;  // (shift in base pixels, frame)
  for (int i = 0; i < solution.frames; ++i) {
    FrameSpec& f = placed[i];
    const PlanarPose& p = solution.poses[i];
    VehiclePose corrected = f.pose;
    corrected.east_m = p.east_m;
    corrected.north_m = p.north_m;
    corrected.heading_deg = p.heading_rad * kRadToDeg;
    if (!solution.nav_only[i]) {
      f.nav_pose = f.pose;
      f.pose = corrected;
    }
    const double shift_px = FootprintShift(camera_, painted_[i], f.pose) / options_.base_pixel_m;
    if (shift_px > options_.repaint_threshold_px) moved.emplace_back(shift_px, i);
  }
  {  // frames handed over since: painted where they were painted
    std::lock_guard<std::mutex> lock(mutex_);
    for (size_t k = 0; k < pending_.size(); ++k) {
      FrameSpec f = pending_[k].first;
      if (Moved(f.pose, painted_in_[k])) f.nav_pose = f.pose;
      f.pose = painted_in_[k];
      placed.push_back(std::move(f));
    }
  }
  std::sort(moved.begin(), moved.end(), std::greater<>());
  if (static_cast<int>(moved.size()) > budget) moved.resize(budget);
  std::vector<int> chosen;
  for (const auto& [shift, i] : moved) chosen.push_back(i);
  std::sort(chosen.begin(), chosen.end());
  for (int i : chosen) correction.before.push_back(painted_[i]);
  correction.moved = chosen;
  solution.poses.clear();
  solution.nav_only.clear();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    correction.solve = ++lag_.solves;
  }
  if (corrected_) corrected_(correction);
  for (int i : chosen) painted_[i] = placed[i].pose;
  std::lock_guard<std::mutex> lock(mutex_);
  lag_.frames_repainted += static_cast<int>(chosen.size());
}

}  // namespace seamap
