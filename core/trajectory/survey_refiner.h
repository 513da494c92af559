#pragma once
// The whole survey at once (refine): every frame's features, every pair of
// overlapping frames registered on the seabed (along the track and, above
// all, across survey lines and loops), and one robust pose graph over all
// frames with the navigation as priors (pose_graph.h). Frames whose
// registrations all fail keep what the navigation says of them, tied to
// their refined neighbours by its relative motion, and are flagged nav_only.
//
// Method kBundle then refines in 3-D: the planar graph's poses
// start a bundle adjustment (survey_bundle.h) over every frame's full
// pose and the seabed points tracked through the registered pairs
// (match_tracks.h); registration looks for matches off the mean plane
// (RegistrationOptions::parallax_share); a survey longer than
// bundle_window_frames is solved in windows (windowed_bundle.h). kPlanar stops at the planar graph:
// the fast path for a flat seabed. kAuto (the default) picks one of them from
// the relief the navigation's depth + altitude shows (refine_method.h).
//
// Features are detected frame by frame in acquisition order and freed once
// the last pair that needs them is registered: memory follows the survey's
// width (frames between a frame and its last partner), not its length.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/image/image_header.h"
#include "core/nav/frame_list.h"
#include "core/terrain/seabed_point.h"
#include "core/trajectory/frame_features.h"
#include "core/trajectory/pair_registration.h"
#include "core/trajectory/refine_method.h"

namespace seamap {

struct RefineOptions {
  RefineMethod method = RefineMethod::kAuto;
  // The navigation's stated noise: white position noise, drift rate, heading noise.
  double nav_noise_m = 0.05;
  double nav_drift_m_per_min = 1.0;
  double heading_noise_deg = 1.0;
  double min_gap_s = 10;     // frames closer in time are along-track neighbours, not cross pairs
  double min_overlap = 0.3;  // predicted overlap for a cross pair
  int max_cross_per_frame = 4;
  int threads = 0;  // 0: one per core
  // Frames whose header claims more pixels are not decoded (the build's max_image_pixels).
  int64_t max_image_pixels = kDefaultMaxImagePixels;
  FeatureOptions features;
  RegistrationOptions registration;
  // kBundle only:
  double relief_share = 0.15;       // heights off the mean plane up to this share of the altitude (parallax_share)
  int max_points_per_frame = 80;    // tracks a frame, in the bundle
  int max_views_per_point = 8;      // views a track keeps, spread over its frames
  double attitude_noise_deg = 0.5;  // AHRS pitch/roll noise
  double depth_noise_m = 0.02, altitude_noise_m = 0.01;  // depth sensor, DVL altitude (metres, 1 sigma)
  double pixel_sigma = 0.7;                              // feature noise, pixels
  // Past this many frames the bundle is solved in windows of it, each solving
  // a quarter more that the next one keeps (windowed_bundle.h): memory bounded,
  // time linear; 0: one bundle up to ReliefChoiceOptions::max_bundle_frames
  // (450), windows of its bundle_window_frames (300) past that.
  int bundle_window_frames = 0;
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
  std::optional<double> navigated_relief_m;  // kAuto: the relief it chose by (refine_method.h)
  std::string method_note;                   // kAuto: why it chose planar over relief, if it did
  // kBundle:
  bool bundle = false;
  int points = 0, observations = 0, observations_rejected = 0;
  int tracks_spread = 0;  // dropped: views too far apart on the level seabed (a wrong match joined two tracks)
  double reprojection_before_px = 0, reprojection_after_px = 0;  // RMS, kept observations
  double seconds_bundle = 0;
  std::string bundle_solver;
  int bundle_iterations = 0;
  int bundle_windows = 0;              // 1: one bundle over the whole survey
  double bundle_seam_jump_max_mm = 0;  // windows: how far a window's first frame moved from the one before's solve
  double bundle_seam_jump_median_mm = 0;
  // Windows: the largest window's problem (frames solved, frames held) and its solves' CPU seconds.
  int bundle_window_solved_frames_max = 0, bundle_window_held_frames_max = 0;
  double bundle_window_cpu_s_max = 0, bundle_window_cpu_s_median = 0;
  double bundle_window_start_rms_px_max = 0;          // the worst window's reprojection RMS where its solve started
  size_t peak_feature_bytes = 0;                      // features held at once
  std::vector<std::pair<std::string, int>> failures;  // registration failures by reason
};

struct RefinedFrame {
  VehiclePose pose;       // refined east, north, heading (kBundle also depth, pitch, roll); the rest as navigated
  bool nav_only = false;  // no registered pair placed it
  // A pair with it was refused as two copies of one photo (identical
  // frames, or no parallax while the navigation moved): a frozen camera.
  bool still_photos = false;
  std::string problem;  // why it has no features, when it has none
};

// frames: in acquisition order, with their navigation poses and times.
// progress(stage, done, total) is called from the caller's thread.
// seabed_points: when given, the bundle's triangulated seabed points (kBundle), for the height model.
std::vector<RefinedFrame> RefineSurvey(const std::vector<FrameSpec>& frames, const CameraModel& camera,
                                       const RefineOptions& options, RefineReport* report,
                                       const std::function<void(const std::string&, int, int)>& progress = nullptr,
                                       SeabedPoints* seabed_points = nullptr);

}  // namespace seamap
