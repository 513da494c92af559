#pragma once
// Refinement as frames arrive (replay --refine-nav): the same features,
// candidate pairs, registrations and planar pose graph as RefineSurvey's
// (survey_refiner.h), grown frame by frame. Add() detects the new frames'
// features and registers every candidate pair among the frames so far that
// was not registered yet (along the track, and across passes and loops as
// the vehicle crosses its earlier lines); Solve() solves the pose graph over
// the frames so far with the pairs of the current candidate set. Once every
// frame of a survey is in, the candidates, the registrations and so the
// solution are RefineSurvey's planar one (a registration depends only on its
// two frames).
//
// Features are about 0.26 MB a frame at 2,000 features. Those of every frame
// would grow with the dive (7 GB at 28,000 frames), so the resident features
// are bounded (max_feature_bytes): past the bound, the features of frames
// whose candidate pairs are all registered are freed, farthest from the
// vehicle's latest position first, and never those of the last frames; a
// later pass that brings a freed frame into a candidate pair extracts its
// features again from its photo. Features depend on the photo only, so the
// registrations, and the solution, do not change; the cost is the extraction
// again of each frame a later pass comes back to.
#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/nav/frame_list.h"
#include "core/trajectory/pair_candidates.h"
#include "core/trajectory/pose_graph.h"
#include "core/trajectory/survey_refiner.h"
#include "core/util/thread_pool.h"

namespace seamap {

struct IncrementalSolution {
  std::vector<PlanarPose> poses;  // one per frame so far, refined (the navigation's where no pair placed it)
  std::vector<bool> nav_only;
  int frames = 0;
  int registered_along = 0, registered_cross = 0;  // pairs of the current candidate set accepted
  int rejected_by_graph = 0;
  // RMS disagreement of the accepted pairs with the navigation and with the
  // solution (RefineReport's residual_before_mm / residual_after_mm): the seams.
  double residual_before_mm = 0, residual_after_mm = 0;
};

// The resident features' bound.
struct FeatureBound {
  size_t max_bytes = 0;    // 0: none, every frame's features kept
  int recent_frames = 50;  // the last frames (where the next pairs come from) keep theirs
};

class IncrementalRefiner {
 public:
  // options.method is not looked at: this is the planar graph.
  IncrementalRefiner(const CameraModel& camera, const RefineOptions& options, FeatureBound bound = {});
  ~IncrementalRefiner();

  // Frames in acquisition order after those added before, with their
  // navigation poses. Returns the cross-pass pairs newly accepted.
  int Add(const std::vector<FrameSpec>& frames);
  // The pose graph over the frames so far.
  IncrementalSolution Solve() const;

  int frames() const { return static_cast<int>(frames_.size()); }
  const std::vector<FrameSpec>& frame_specs() const { return frames_; }  // as added
  size_t feature_bytes() const { return feature_bytes_; }                // resident now
  size_t peak_feature_bytes() const { return peak_feature_bytes_; }      // the most resident at once
  int features_freed() const { return features_freed_; }                 // frames whose features were freed
  int features_again() const { return features_again_; }                 // extracted again for a later pair
  // Frees every frame's features (the worker is done); Add extracts what it needs again.
  void FreeFeatures();

 private:
  struct Prepared;
  std::unique_ptr<Prepared> Prepare(int i) const;  // frame i's features and registration frame
  void Keep(int i, std::unique_ptr<Prepared> p);   // as prepared_[i], counted
  void Free(int i);                                // frame i's features freed (it can be prepared again)
  void Bound();                                    // frees features past bound_.max_bytes
  CameraModel camera_;
  RefineOptions options_;
  double nav_noise_m_, drift_m_per_s_, heading_noise_rad_;
  std::unique_ptr<ThreadPool> pool_;
  std::vector<FrameSpec> frames_;
  std::vector<double> times_;
  std::vector<CandidateFrame> candidate_frames_;
  std::vector<std::unique_ptr<Prepared>> prepared_;
  std::vector<CandidatePair> candidates_;                   // among the frames so far
  std::map<std::pair<int, int>, PairConstraint> accepted_;  // registered pairs that were accepted
  std::map<std::pair<int, int>, bool> tried_;
  FeatureBound bound_;
  size_t feature_bytes_ = 0, peak_feature_bytes_ = 0;
  int features_freed_ = 0, features_again_ = 0;
};

}  // namespace seamap
