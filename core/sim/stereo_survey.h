#pragma once
// `seamap simulate-stereo`: a virtual wellhead on the seabed seen by a
// downward-looking stereo rig (1200 x 900, f = 1040 px, 0.25 m baseline),
// overview pairs 3.6 m above the object's top to build the model, approach
// pairs 3.0-4.2 m above it (headings up to 45 deg apart, offsets up to 1 m,
// 0.3-0.8 m between pairs) to locate it, one pair without the object, and
// the exact truth (truth/poses.json, truth/check_points.csv).
//
// With dive_sightings N: a dive on the Earth (dive/, `stereo-locate --pairs
// dive/ --nav dive/nav.csv`): the vehicle (its navigation point is the left
// camera) passes over the object N times on straight 0.5 m/s legs, and a pair
// is taken mid-leg (named dive_SSSS.SSS: its time in seconds); one more pair,
// over the object after the navigation ends, must be skipped. dive/nav.csv is
// the vehicle's exact trajectory (1 s steps, linear within a leg, so its
// interpolation is exact at the pairs' times); truth/dive.json the object's
// frame (the model's: the first overview pair's left camera) on the Earth.
#include <cstdint>
#include <map>
#include <string>

#include "core/sim/stereo_renderer.h"
#include "core/sim/stereo_scene.h"
#include "core/stereo/rigid_transform.h"

namespace seamap {

struct StereoSurveyOptions {
  std::string out_dir;
  bool force = false;
  uint64_t seed = 1;
  int views = 3;                 // overview pairs and approach pairs
  double object_texture = 1;     // 1 fouled steel, ~0.15 plain paint
  double approach_offset_m = 1;  // the approach's first pair lies within this of the object's axis
  // motion.json: the approach poses as navigation would measure them, this noisy per axis.
  double motion_sigma_m = 0.001, motion_sigma_deg = 0.01;
  int dive_sightings = 0;  // 0: no dive
  double dive_origin_lat = 43.1, dive_origin_lon = 131.9, dive_seabed_depth_m = 30;
  StereoRenderOptions render;
  void Check() const;
};

struct StereoSurveySummary {
  std::map<std::string, Rigid> overview, approach;  // object_from_camera (left), scene frame
  std::string layout;
  double seconds = 0;
};

StereoSurveySummary SimulateStereoSurvey(const StereoSurveyOptions& options);

// The rig simulate-stereo writes to stereo.yaml.
StereoCalibration SimulatedStereoRig();

}  // namespace seamap
