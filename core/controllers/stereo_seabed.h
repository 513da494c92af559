#pragma once
// `seamap stereo-points`: a stereo rig's pairs as seabed points for the
// height model (`build --terrain --terrain-points FILE`). Every pair of a
// folder is matched and triangulated (core/stereo/stereo_matcher.h), placed
// at its time on the vehicle's navigation through the rig's mounting, and
// written as one CSV row per point: pair, lat, lon, up_m (metres up: the sea
// surface's datum when the navigation has depth_m), sigma_up_m. Latitude and
// longitude, so that a build with another origin reads them in its own frame.
#include <optional>
#include <string>
#include <vector>

#include "core/enhance/chain_choice.h"
#include "core/geo/local_frame.h"
#include "core/stereo/object_georef.h"
#include "core/stereo/sift_features.h"
#include "core/stereo/stereo_matcher.h"
#include "core/stereo/stereo_seabed_points.h"

namespace seamap {

struct StereoPointsOptions {
  std::string calib_path, pairs_dir, nav_path;
  std::string out;                             // the points' CSV
  std::optional<std::string> pair_times_path;  // else each pair's time from its name
  std::optional<LatLon> origin;                // the navigation's local frame (as build --origin)
  RigMount mount;
  SiftOptions sift;
  StereoMatchOptions match;
  StereoSeabedOptions points;
  FeatureEnhanceOptions feature_enhance;
  bool quiet = false;
  void Check() const;  // InputError naming the option
};

struct StereoPointsReport {
  int pairs = 0, used = 0;
  std::vector<std::string> skipped;  // "pair: why" (outside the navigation's times, not a pair)
  long points = 0;
  std::string chain = "none";  // the enhancement chain used
};

// Reads, matches and writes pair by pair (one pair in memory at a time).
// InputError naming the file for a calibration, navigation or time that
// does not fit; a pair outside the navigation's times is skipped and reported.
StereoPointsReport WriteStereoSeabedPoints(const StereoPointsOptions& options);

// Reads such a CSV into `frame`'s local metres (build --terrain-points);
// InputError naming the file, line and column. At most max_points rows.
SeabedPoints ReadStereoSeabedPoints(const std::string& path, const LocalFrame& frame, long max_points = 20'000'000);

}  // namespace seamap
