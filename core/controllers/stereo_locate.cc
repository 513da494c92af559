#include "core/controllers/stereo_locate.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/geo/local_frame.h"
#include "core/mission/detection_book.h"
#include "core/mission/mission_metadata.h"
#include "core/nav/nav_reader.h"
#include "core/nav/nav_series.h"
#include "core/stereo/icp_baseline.h"
#include "core/stereo/object_model.h"
#include "core/stereo/stereo_calibration.h"
#include "core/stereo/stereo_pairs.h"
#include "core/util/error.h"

namespace seamap {
namespace {

// The first `views` pairs of the folder, checked against the calibration.
std::vector<LoadedPair> LoadPairs(const StereoLocateOptions& o, const StereoCalibration& calibration) {
  std::vector<PairFiles> files = ListStereoPairs(o.pairs_dir);
  if (static_cast<int>(files.size()) < o.views)
    throw InputError(o.pairs_dir, 0, "--views",
                     cv::format("asked for %d pairs, the folder has %zu", o.views, files.size()));
  files.resize(o.views);
  std::vector<LoadedPair> pairs;
  for (const PairFiles& f : files) pairs.push_back(LoadStereoPair(f, calibration.image_size, o.calib_path));
  return pairs;
}

// The vehicle's pose at time_s, in the navigation's local frame (about `origin` when given).
std::pair<VehiclePose, LocalFrame> VehicleAt(const std::string& nav_path, double time_s,
                                             const std::optional<LatLon>& origin) {
  NavReadOptions nav_options;
  nav_options.origin = origin;
  const NavTable nav = ReadNavigation(nav_path, nav_options);
  if (!nav.has_times) throw InputError(nav_path, 0, "time_s", "the navigation has no times to interpolate at --time");
  // Sorted by time, as build places its frames: unsorted navigation gives the same pose.
  const NavSeries series(nav.records);
  const std::optional<VehiclePose> vehicle = series.PoseAt(time_s);
  if (!vehicle)
    throw InputError(nav_path, 0, "--time",
                     cv::format("%.3f s is outside the navigation's times (%.3f to %.3f s)", time_s,
                                series.empty() ? 0 : series.first_time_s(), series.empty() ? 0 : series.last_time_s()));
  return {*vehicle, LocalFrame(nav.origin)};
}

}  // namespace

void StereoLocateOptions::Check() const {
  if (views < 1) throw InputError("", 0, "--views", "expected a positive number of pairs");
  if (method != "features" && method != "icp") throw InputError("", 0, "--method", "expected features or icp");
  if (map_path && !nav_path) throw InputError("", 0, "--map", "needs --nav and --time: where the vehicle was");
  if (nav_path.has_value() != time_s.has_value())
    throw InputError("", 0, nav_path ? "--time" : "--nav", "--nav and --time go together");
}

StereoLocate::StereoLocate(StereoLocateOptions options) : options_(std::move(options)) {}

StereoLocation StereoLocate::Run() {
  const StereoLocateOptions& o = options_;
  o.Check();
  const StereoCalibration calibration = LoadStereoCalibration(o.calib_path);
  const ObjectModel model = LoadObjectModel(o.model_path);
  if (model.image_size != calibration.image_size)
    throw InputError(o.model_path, 0, "calibration.image_size",
                     cv::format("the model was built from %dx%d images, %s is for %dx%d", model.image_size.width,
                                model.image_size.height, o.calib_path.c_str(), calibration.image_size.width,
                                calibration.image_size.height));
  if (std::abs(model.fx_px / calibration.K1(0, 0) - 1) > 0.02 ||
      std::abs(model.baseline_m / cv::norm(calibration.T) - 1) > 0.02)
    std::fprintf(stderr, "seamap stereo-locate: warning: %s was built with another rig (fx %.0f px, baseline %.3f m)\n",
                 o.model_path.c_str(), model.fx_px, model.baseline_m);
  const std::vector<LoadedPair> pairs = LoadPairs(o, calibration);

  // Where the vehicle was, before the (slow) search: bad navigation is reported first.
  store_ = o.map_path ? OpenExistingMap(*o.map_path, /*writable=*/true) : nullptr;
  // The mission's origin: the navigation's local frame, and so the detection's position_m, is the mission's.
  const std::optional<LatLon> origin =
      store_ ? std::optional<LatLon>(RequireMissionOrigin(ReadMissionMetadata(*store_), *o.map_path)) : std::nullopt;
  std::optional<std::pair<VehiclePose, LocalFrame>> vehicle;
  if (o.nav_path) vehicle = VehicleAt(*o.nav_path, *o.time_s, origin);

  StereoLocation located;
  located.model_name = model.name;
  if (o.method == "icp") {
    IcpOptions icp;
    icp.sift = o.locate.sift;
    icp.match = o.locate.match;
    located.result = LocateObjectIcp(model, calibration, pairs, icp);
  } else {
    located.result = LocateObject(model, calibration, pairs, o.locate);
  }
  nlohmann::json pose_json = LocateResultToJson(located.result, model.name);
  if (located.result.found && vehicle) {
    located.placed = PlaceObject(located.result.object_from_camera, o.mount, vehicle->first, vehicle->second);
    pose_json["geo"] = {{"lat", located.placed->position.lat},
                        {"lon", located.placed->position.lon},
                        {"depth_m", located.placed->depth_m},
                        {"heading_deg", located.placed->heading_deg},
                        {"time_s", *o.time_s}};
  }
  std::ofstream file(o.out);
  if (!file) throw InputError(o.out, 0, "--out", "cannot write the pose");
  file << pose_json.dump(2) << "\n";
  return located;
}

long long StereoLocate::StoreDetection(const StereoLocation& location) {
  if (!store_ || !location.placed) throw std::logic_error("StoreDetection: no map, or nothing placed in it");
  const PlacedObject& placed = *location.placed;
  Detection d;
  d.class_name = location.model_name;
  d.source = "stereo";
  d.model = std::filesystem::path(options_.model_path).filename().string();
  d.score = 1;
  d.position = placed.position;
  d.position_m = std::array<double, 2>{placed.local.east, placed.local.north};  // the mission's frame
  d.heading_deg = placed.heading_deg;
  d.depth_m = placed.depth_m;
  d.time_s = *options_.time_s;
  d.status = "unconfirmed";
  // Located again within 10 cm (same model file): the same detection, its review kept.
  d = PublishFound(*store_, {d}, d.model, {d.class_name})[0];
  store_->Flush();
  return static_cast<long long>(d.id);
}

}  // namespace seamap
