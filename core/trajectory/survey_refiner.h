#pragma once
// The whole survey at once (refine): every frame's features, every pair of
// overlapping frames registered on the seabed (along the track and, above
// all, across survey lines and loops), and one robust pose graph over all
// frames with the navigation as priors (pose_graph.h). Frames whose
// registrations all fail keep what the navigation says of them, tied to
// their refined neighbours by its relative motion, and are flagged nav_only.
#include <functional>
#include <string>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/nav/frame_list.h"
#include "core/trajectory/frame_features.h"
#include "core/trajectory/pair_registration.h"

namespace seamap {

struct RefineOptions {
  // The navigation's stated noise: white position noise, drift rate, heading noise.
  double nav_noise_m = 0.05;
  double nav_drift_m_per_min = 1.0;
  double heading_noise_deg = 1.0;
  double min_gap_s = 10;     // frames closer in time are along-track neighbours, not cross pairs
  double min_overlap = 0.3;  // predicted overlap for a cross pair
  int max_cross_per_frame = 4;
  int threads = 0;  // 0: one per core
  FeatureOptions features;
  RegistrationOptions registration;
  void Check() const;  // InputError naming the option as the command line spells it
};

struct RefineReport {
  int frames = 0, frames_without_features = 0, nav_only = 0;
  int pairs_along = 0, pairs_cross = 0;            // tried
  int registered_along = 0, registered_cross = 0;  // accepted by registration
  int rejected_by_graph = 0;                       // accepted, then dropped by the pose graph
  double median_inliers = 0;
  double residual_before_mm = 0, residual_after_mm = 0;  // RMS disagreement of the registered pairs
  double seconds_features = 0, seconds_pairs = 0, seconds_solve = 0;
  std::vector<std::pair<std::string, int>> failures;  // registration failures by reason
};

struct RefinedFrame {
  VehiclePose pose;       // refined east, north, heading; the rest as navigated
  bool nav_only = false;  // no registered pair placed it
  std::string problem;    // why it has no features, when it has none
};

// frames: in acquisition order, with their navigation poses and times.
// progress(stage, done, total) is called from the caller's thread.
std::vector<RefinedFrame> RefineSurvey(const std::vector<FrameSpec>& frames, const CameraModel& camera,
                                       const RefineOptions& options, RefineReport* report,
                                       const std::function<void(const std::string&, int, int)>& progress = nullptr);

}  // namespace seamap
