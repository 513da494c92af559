#pragma once
// The camera's pose in the object's frame from stereo pairs, and with the
// vehicle's trajectory where the object is on the Earth: what `seamap
// stereo-locate` runs (docs/STEREO.md). Writes the pose file; stores the
// placed object in a mission as a detection (source "stereo") on request.
//
// The trajectory is a navigation file (--nav) or the mission's own (--map
// alone: the poses its frames were placed with, refined or estimated where
// they were; core/mission/mission_trajectory.h). With --time, the first N
// pairs are located jointly at that time; without it (a dive), every pair is
// located on its own at its own time (--pair-times or its name,
// core/stereo/pair_times.h), each sighting placed and stored.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/enhance/chain_choice.h"
#include "core/geo/local_frame.h"
#include "core/stereo/object_georef.h"
#include "core/stereo/object_locator.h"
#include "core/stereo/object_model.h"
#include "core/stereo/stereo_calibration.h"
#include "core/stereo/stereo_pairs.h"
#include "core/tiles/tile_store.h"

namespace seamap {

struct StereoLocateOptions {
  std::string calib_path, model_path, pairs_dir;
  std::string out;                  // pose.json
  int views = 1;                    // the first N pairs of pairs_dir (sorted by name), jointly
  std::string method = "features";  // or "icp" (the baseline)
  LocateOptions locate;             // the features method's found rule, tie points, rig motion, SIFT
  // Seed 004's chain in front of the SIFT features (--feature-enhance): off,
  // a chain, or auto (the first pairs tell whether one raises the stereo
  // inliers; core/stereo/stereo_enhancement.h).
  FeatureEnhanceOptions feature_enhance;
  // Where the object is on the Earth: the navigation (else the mission's
  // trajectory) and when the first pair used was taken (in its clock), and
  // the rig on the vehicle.
  std::optional<std::string> nav_path;
  std::optional<double> time_s;
  RigMount mount;
  std::optional<std::string> map_path;  // the mission the object is stored in; its trajectory without nav_path
  // A dive (no time_s): each pair's time from this table (else its name).
  std::optional<std::string> pair_times_path;
  bool quiet = false;  // no progress bar
  // Every pair on its own at its own time: a trajectory and no --time.
  bool Dive() const { return !time_s && (nav_path || map_path); }
  // InputError naming the option that does not fit (--views, --method, --map, --nav, --time, --pair-times, --motion).
  void Check() const;
};

// One pair of a dive: located (or not) at its time, or skipped.
struct StereoSighting {
  std::string pair;
  std::optional<double> time_s;
  std::string time_from;  // "--pair-times" or "name"
  std::string skipped;    // why it was not searched (outside the trajectory's times); empty otherwise
  LocateResult result;
  std::optional<PlacedObject> placed;  // found
};

struct StereoDive {
  std::string model_name, trajectory;  // trajectory: what the poses came from, for the user
  std::vector<StereoSighting> sightings;
  nlohmann::json summary;  // pairs, found, not_found, skipped, mean position and spread of the found
};

struct StereoLocation {
  LocateResult result;
  std::string model_name;
  std::optional<PlacedObject> placed;  // found, with nav_path and time_s
};

// The pieces a dive is made of, for whoever locates pairs as a dive goes
// (core/controllers/live_stereo.h): the calibration and model checked
// against each other; the pairs located with options' method; every pair of
// `files` with its time (from --pair-times, else its name: InputError naming
// the pair without one); the found sightings grouped as objects, one
// detection each (sightings within 1 m of a group's mean are one object).
std::pair<StereoCalibration, ObjectModel> LoadStereoRig(const StereoLocateOptions& options);
LocateResult LocateStereoPairs(const StereoLocateOptions& options, const ObjectModel& model,
                               const StereoCalibration& calibration, const std::vector<LoadedPair>& pairs);
std::vector<StereoSighting> TimedSightings(const StereoLocateOptions& options, const std::vector<PairFiles>& files);
// A placed object as the mission stores it (source "stereo", the model file's name as its model).
// sigma_m: the position's horizontal uncertainty, stored on the record (none: unknown).
Detection StereoSightingDetection(const StereoLocateOptions& options, const PlacedObject& placed, double time_s,
                                  std::optional<double> sigma_m = std::nullopt);
std::vector<Detection> StereoObjectDetections(const StereoLocateOptions& options,
                                              const std::vector<StereoSighting>& sightings,
                                              const std::string& model_name, const LocalFrame& frame);

class StereoLocate {
 public:
  explicit StereoLocate(StereoLocateOptions options);
  // Loads the calibration, model and pairs, opens the map and interpolates
  // the navigation (all before the slow search), locates the object and
  // writes options.out. InputError naming what does not fit; a warning on
  // stderr when the model was built with another rig. Not found is a result.
  StereoLocation Run();
  // A dive (options.Dive()): every pair of pairs_dir located on its own at its
  // time, placed on the trajectory; writes options.out (sightings + summary).
  // A pair without a time is an InputError naming it; one outside the
  // trajectory's times is skipped with the reason.
  StereoDive RunDive();
  // With map_path: stores every placed sighting (one detection per object:
  // sightings within 10 cm of each other are the same one); returns the ids.
  std::vector<long long> StoreDetections(const StereoDive& dive);
  // With map_path: stores the placed object as a detection, replacing its
  // earlier location (found again within 10 cm, same model file: the same
  // detection, its review kept); returns its id.
  long long StoreDetection(const StereoLocation& location);

 private:
  StereoLocateOptions options_;
  // The vehicle's trajectory, about the mission's origin when there is a map.
  struct Trajectory;
  std::unique_ptr<Trajectory> OpenTrajectory();
  Detection SightingDetection(const PlacedObject& placed, double time_s) const;
  // Sets options_.locate.sift.enhance from the probe pairs; what was chosen, for the pose file.
  nlohmann::json ChooseEnhancement(const std::vector<LoadedPair>& probe, const StereoCalibration& calibration);

  std::unique_ptr<TileStore> store_;  // map_path, opened by Run
};

}  // namespace seamap
