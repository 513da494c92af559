#pragma once
// SLAM keyframes (and their point cloud) put into real-world coordinates
// from the GPS fixes of a buoy towed on a tether: what `seamap georef` runs.
// Reads the keyframes, buoy, depth and altitude logs, fits each sub-map
// (core/georef/georeferencer.h), and writes nav.csv, the report and the
// georeferenced cloud.
#include <optional>
#include <string>
#include <vector>

#include "core/geo/lat_lon.h"
#include "core/geo/utm.h"
#include "core/georef/georef_options.h"
#include "core/georef/georeferencer.h"
#include "core/georef/tum_trajectory.h"

namespace seamap {

struct BuoyGeorefOptions {
  std::vector<std::string> keyframe_files;  // TUM trajectories, one per sub-map, or ...
  // ... a mission (--map): the trajectory its frames were placed with, in its
  // local frame (east, north, up), as one sub-map's keyframes
  // (core/controllers/mission_trajectory_io.h).
  std::string map_path;
  // ... or keyframes already in memory (`seamap trajectory --buoy`: its own
  // estimate), named `keyframes_source` in messages; set the name before Check().
  std::vector<Keyframe> keyframes;
  std::string keyframes_source;
  std::string buoy_file;
  double tether_length_m = 0;
  std::optional<double> depth_m;                         // constant depth, or ...
  std::string depth_file;                                // ... a depth log, or ...
  std::vector<std::pair<double, double>> depth_samples;  // ... (time_s, depth_m) in memory
  std::string out;                 // nav.csv ("": none, the caller writes what it needs from the result)
  std::string report;              // "": none
  std::string points, points_out;  // the PLY cloud in and georeferenced out ("": none)
  GeorefOptions georef;
  std::optional<LatLon> origin;  // the working frame's centre (the cloud in local metres about it)
  std::optional<UtmZoneId> utm_zone;
  std::string altitude_file;         // altitude log for nav.csv's altitude_m, or ...
  bool altitude_from_cloud = false;  // ... altitude from the cloud below each keyframe
  bool quiet = false;                // only degenerate sub-maps' summaries
  // InputError naming the option that does not fit.
  void Check() const;
};

struct BuoyGeorefResult {
  int keyframes = 0, good = 0;
  int submaps = 0;
  std::vector<SubmapGeoref> fits;  // each sub-map's fit, its keyframes in the working frame
  LatLon working_origin;           // the working frame's centre (--origin, else the buoy track's median)
};

class BuoyGeoref {
 public:
  explicit BuoyGeoref(BuoyGeorefOptions options);
  // Warnings, skipped lines and sub-map summaries go to stderr. InputError
  // for bad input and for a sub-map that cannot be georeferenced.
  BuoyGeorefResult Run();

 private:
  BuoyGeorefOptions options_;
};

}  // namespace seamap
