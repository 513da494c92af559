#pragma once
// Which refinement a survey needs (RefineMethod::kAuto, the default): the
// planar pose graph where the seabed is flat, the bundle adjustment over
// relief. The navigation already tells: the seabed under the vehicle is at
// depth + altitude, and its variation along the track within a few seconds
// (a window shorter than a lane, so a gently sloping site does not count) is
// the relief the registration's flat-seabed model would trip over. Relief
// above min_relief_share of the altitude (rms; 1 cm at 2 m) picks the bundle:
// at 0.05 m rms relief the planar refinement's cross-pass p90 is already
// ~70 mm (issue 29), on a flat seabed both agree.
#include <optional>
#include <string>
#include <vector>

#include "core/nav/frame_list.h"

namespace seamap {

enum class RefineMethod { kPlanar, kBundle, kAuto };

struct ReliefChoiceOptions {
  double window_s = 5;              // the local mean's half-width, seconds
  double min_relief_share = 0.005;  // of the median altitude: relief above it picks the bundle
  // Past this many frames the bundle is solved in windows of
  // bundle_window_frames (windowed_bundle.h; memory bounded by the window,
  // time linear in the survey) and the choice says so; 0: no limit. One
  // bundle grows ~0.65 MB a frame and its time faster than the survey: on the
  // rugged 720-frame surveys windows of 300 are as accurate (p90 6.2-6.4 mm
  // on three seeds, ATE within 1.7 mm) at 58 % of the CPU and 62 % of the
  // memory (docs/BUNDLE_WINDOWS.md, "Windows of 300 by default").
  int max_bundle_frames = 450;
  int bundle_window_frames = 300;
};

struct ReliefChoice {
  RefineMethod method = RefineMethod::kPlanar;
  std::optional<double> relief_rms_m;  // the seabed's local variation along the track; none without altitude and depth
  double altitude_m = 0;               // median altitude
  // kBundle past max_bundle_frames: the window the bundle is solved in; 0: one bundle.
  int bundle_window_frames = 0;
  std::string note;  // the bundle in windows on a survey too long for one; empty otherwise
};

// times_s: one per frame, non-decreasing. Frames without an altitude (0) are
// left out; fewer than 10 with one: planar (nothing says the seabed is rough).
ReliefChoice ChooseRefineMethod(const std::vector<FrameSpec>& frames, const std::vector<double>& times_s,
                                const ReliefChoiceOptions& options = {});

}  // namespace seamap
