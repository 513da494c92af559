#pragma once
// The worker of replay --refine-nav: frames are handed to it as they are
// painted (Add never waits), it refines their navigation as they come
// (IncrementalRefiner: features, pairs along the track and across passes
// and loops, the planar pose graph), and after a solve hands back, through
// `corrected`, every frame's corrected pose and which frames' placement moved
// more than a base pixel since they were painted, so they can be painted
// again. It solves when new cross-pass pairs have arrived (a loop closed)
// and at least `min_frames_between_solves` frames came since the last solve;
// frames that came meanwhile are taken together, up to max_batch_frames (it batches when behind).
// At most `repaint_share` moved frames per new frame are handed back a
// solve, the most moved first; the rest wait for the next one, so
// repainting stays a bounded share of the painting.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/nav/frame_list.h"
#include "core/trajectory/incremental_refiner.h"

namespace seamap {

struct LiveRefinerOptions {
  RefineOptions refine;
  double base_pixel_m = 0.003;        // a base-zoom pixel on the seabed, metres
  double repaint_threshold_px = 1.0;  // a frame whose footprint moved more is painted again
  int min_frames_between_solves = 10;
  double repaint_share = 2.0;
  // The worker's resident features at most this (IncrementalRefiner's bound;
  // 0: none): about 2,000 frames at 2,000 features.
  size_t max_feature_bytes = size_t{512} << 20;
  // Frames taken at once when behind: the features held past the bound are at most one batch's.
  int max_batch_frames = 25;
  void Check() const;  // InputError naming the option
};

// How far the worker is behind the frames painted, and what it did.
struct LiveRefinerLag {
  int frames_behind = 0;      // handed over, not yet refined
  double seconds_behind = 0;  // since the oldest of them was handed over
  double worst_seconds = 0;   // the most seconds_behind has been
  int solves = 0;
  int frames_repainted = 0;    // handed back as moved
  int cross_pairs = 0;         // accepted across passes so far
  bool failed = false;         // the worker stopped on an error (said on stderr)
  double peak_feature_mb = 0;  // the most features resident at once
  int features_freed = 0;      // frames whose features were freed (past max_feature_bytes)
  int features_again = 0;      // frames whose features were extracted again for a later pass
};

// A solve's outcome, handed back on the worker's thread.
struct LiveCorrection {
  // Every frame handed over so far, each at the pose it is placed at now (the
  // navigation's in nav_pose where that differs).
  std::vector<FrameSpec> placed;
  std::vector<int> moved;           // indices into placed of the frames to paint again
  std::vector<VehiclePose> before;  // the poses they were painted at
  int solve = 0;                    // 1 for the first
  IncrementalSolution solution;     // poses dropped: they are in placed
};

class LiveRefiner {
 public:
  using Corrected = std::function<void(const LiveCorrection&)>;

  LiveRefiner(const CameraModel& camera, LiveRefinerOptions options, Corrected corrected);
  ~LiveRefiner();  // Stop()

  // A frame as it is painted: its navigation pose (`nav.pose`) and the
  // pose it was painted at. Acquisition order. Never waits.
  void Add(const FrameSpec& nav, const VehiclePose& painted);
  // Stops after the solve under way (frames not refined yet are left to the final solve); joins.
  void Stop();
  LiveRefinerLag Lag() const;

 private:
  using Clock = std::chrono::steady_clock;
  void Work();
  void SolveAndHandBack();

  CameraModel camera_;
  LiveRefinerOptions options_;
  Corrected corrected_;
  IncrementalRefiner refiner_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::pair<FrameSpec, Clock::time_point>> pending_;
  std::vector<VehiclePose> painted_;     // the pose each frame was last painted at (worker's, once taken)
  std::vector<VehiclePose> painted_in_;  // handed over with Add, not yet taken (mutex_)
  Clock::time_point batch_since_;        // when the oldest frame being refined was handed over (mutex_)
  bool stop_ = false;
  int frames_since_solve_ = 0, cross_since_solve_ = 0;
  LiveRefinerLag lag_;  // mutex_
  std::thread worker_;  // last: it uses the members above
};

}  // namespace seamap
