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
// Features are kept for every frame (a later pass may pair with any of
// them): memory grows with the survey, about 0.26 MB a frame at 2,000
// features, unlike RefineSurvey's, which follows the survey's width.
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

class IncrementalRefiner {
 public:
  // options.method is not looked at: this is the planar graph.
  IncrementalRefiner(const CameraModel& camera, const RefineOptions& options);
  ~IncrementalRefiner();

  // Frames in acquisition order after those added before, with their
  // navigation poses. Returns the cross-pass pairs newly accepted.
  int Add(const std::vector<FrameSpec>& frames);
  // The pose graph over the frames so far.
  IncrementalSolution Solve() const;

  int frames() const { return static_cast<int>(frames_.size()); }
  const std::vector<FrameSpec>& frame_specs() const { return frames_; }  // as added
  size_t feature_bytes() const { return feature_bytes_; }

 private:
  struct Prepared;
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
  size_t feature_bytes_ = 0;
};

}  // namespace seamap
