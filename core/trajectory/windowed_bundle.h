#pragma once
// The bundle adjustment of a long survey in windows (docs/BUNDLE_WINDOWS.md,
// "The bundle in windows (scaling)"): one global bundle (survey_bundle.h) grows ~0.65 MB a frame and
// its time faster than the survey, so past `window_frames` the frames are
// solved in acquisition order, a window at a time. Each window solves its
// frames plus `overlap_frames` beyond them (so that its last frames see what
// follows), every seabed point those frames observe, and holds (near where
// it was solved, SurveyBundleOptions::held_sigma_m) every
// frame already solved that observes one of those points: the frames just
// before (the seam) and the earlier lanes' cross-pass partners. Only the
// window's own frames are kept; the overlap is solved again, from there, by
// the next window. The navigation's drift knots are the survey's: a window
// holds those before its first kept frame where earlier windows solved them
// (SurveyBundleDrift), and its frames not yet solved start moved by the
// correction the window before gave its last frame. After each window,
// everything solved so far turns and scales as one to where the headings
// and the altitudes measured so far say: the windows' held lanes fix the
// lanes' turn and size relative to each other, the headings their turn as a
// whole and the altimeter their scale. Memory is bounded by the
// window, time grows with the survey. A survey of at most window_frames
// frames is one global bundle, exactly as SolveSurveyBundle solves it.
#include <functional>
#include <vector>

#include "core/trajectory/survey_bundle.h"

namespace seamap {

struct WindowedBundleOptions {
  int window_frames = 400;   // frames kept per window; 0: one global bundle however long the survey
  int overlap_frames = 100;  // frames solved past the window's end, kept by the next window
  void Check() const;        // InputError naming the option as the command line spells it
};

// What one window's solve held and cost (docs/BUNDLE_WINDOWS.md, "The windows' cost at 3,800 frames").
struct WindowCost {
  int first_kept_frame = 0, end_kept_frame = 0;  // the frames it keeps, [first, end)
  int solved_frames = 0;                         // kept + overlap, free in its problem
  int held_frames = 0;                           // earlier frames held fixed (the seam, cross-pass partners)
  int points = 0, observations = 0, iterations = 0;
  double cpu_s = 0;  // process CPU time of its solve, all threads
  // Reprojection RMS of its observations where its solve started, pixels: how
  // far its new frames and points started from the solved ones they share.
  double start_rms_px = 0;
};

struct WindowedBundleReport {
  int windows = 0;
  // Where consecutive windows meet: how far the first frame a window keeps
  // moved from where the window before solved it (its overlap), metres; the
  // step between the two windows' frames differs from one solve's by this much.
  double max_seam_jump_m = 0, median_seam_jump_m = 0;
  int max_window_frames = 0;             // frames in the largest window's problem, fixed ones included
  std::vector<WindowCost> window_costs;  // per window, in order (empty for one global bundle)
};

// As SolveSurveyBundle (same inputs, same result), in windows past
// window.window_frames frames. progress(done, total) counts windows.
SurveyBundleResult SolveWindowedBundle(const std::vector<SurveyBundleFrame>& frames, const CameraModel& camera,
                                       const std::vector<Eigen::Vector3d>& points_start,
                                       const std::vector<SurveyBundleObservation>& observations,
                                       const SurveyBundleOptions& options, const WindowedBundleOptions& window,
                                       WindowedBundleReport* report = nullptr,
                                       const std::function<void(int, int)>& progress = nullptr);

}  // namespace seamap
