#pragma once
// The camera's pose in the object's frame from stereo pairs, and with the
// vehicle's navigation where the object is on the Earth: what `seamap
// stereo-locate` runs (docs/STEREO.md). Writes the pose file; stores the
// placed object in a mission as a detection (source "stereo") on request.
#include <memory>
#include <optional>
#include <string>

#include "core/stereo/object_georef.h"
#include "core/stereo/object_locator.h"
#include "core/tiles/tile_store.h"

namespace seamap {

struct StereoLocateOptions {
  std::string calib_path, model_path, pairs_dir;
  std::string out;                  // pose.json
  int views = 1;                    // the first N pairs of pairs_dir (sorted by name), jointly
  std::string method = "features";  // or "icp" (the baseline)
  LocateOptions locate;             // the features method's found rule, tie points, rig motion, SIFT
  // Where the object is on the Earth: the navigation and when the first pair
  // used was taken (in its clock), and the rig on the vehicle.
  std::optional<std::string> nav_path;
  std::optional<double> time_s;
  RigMount mount;
  std::optional<std::string> map_path;  // the mission the object is stored in (needs nav_path)
  // InputError naming the option that does not fit (--views, --method, --map, --nav or --time).
  void Check() const;
};

struct StereoLocation {
  LocateResult result;
  std::string model_name;
  std::optional<PlacedObject> placed;  // found, with nav_path and time_s
};

class StereoLocate {
 public:
  explicit StereoLocate(StereoLocateOptions options);
  // Loads the calibration, model and pairs, opens the map and interpolates
  // the navigation (all before the slow search), locates the object and
  // writes options.out. InputError naming what does not fit; a warning on
  // stderr when the model was built with another rig. Not found is a result.
  StereoLocation Run();
  // With map_path: stores the placed object as a detection, replacing its
  // earlier location (found again within 10 cm, same model file: the same
  // detection, its review kept); returns its id.
  long long StoreDetection(const StereoLocation& location);

 private:
  StereoLocateOptions options_;
  std::unique_ptr<TileStore> store_;  // map_path, opened by Run
};

}  // namespace seamap
