#include "core/controllers/stereo_locate.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <stdexcept>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/controllers/mission_trajectory_io.h"
#include "core/geo/local_frame.h"
#include "core/mission/detection_book.h"
#include "core/mission/mission_metadata.h"
#include "core/nav/csv_table.h"
#include "core/nav/nav_reader.h"
#include "core/nav/nav_series.h"
#include "core/stereo/icp_baseline.h"
#include "core/stereo/object_model.h"
#include "core/stereo/pair_times.h"
#include "core/stereo/stereo_calibration.h"
#include "core/stereo/stereo_enhancement.h"
#include "core/stereo/stereo_pairs.h"
#include "core/util/error.h"
#include "core/util/progress.h"

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

void WriteJson(const std::string& path, const nlohmann::json& j) {
  std::ofstream file(path);
  if (!file) throw InputError(path, 0, "--out", "cannot write the pose");
  file << j.dump(2) << "\n";
}

// The calibration and the model, checked against each other.
std::pair<StereoCalibration, ObjectModel> LoadRig(const StereoLocateOptions& o) {
  StereoCalibration calibration = LoadStereoCalibration(o.calib_path);
  ObjectModel model = LoadObjectModel(o.model_path);
  if (model.image_size != calibration.image_size)
    throw InputError(o.model_path, 0, "calibration.image_size",
                     cv::format("the model was built from %dx%d images, %s is for %dx%d", model.image_size.width,
                                model.image_size.height, o.calib_path.c_str(), calibration.image_size.width,
                                calibration.image_size.height));
  if (std::abs(model.fx_px / calibration.K1(0, 0) - 1) > 0.02 ||
      std::abs(model.baseline_m / cv::norm(calibration.T) - 1) > 0.02)
    std::fprintf(stderr, "seamap stereo-locate: warning: %s was built with another rig (fx %.0f px, baseline %.3f m)\n",
                 o.model_path.c_str(), model.fx_px, model.baseline_m);
  return {std::move(calibration), std::move(model)};
}

LocateResult LocateWith(const StereoLocateOptions& o, const ObjectModel& model, const StereoCalibration& calibration,
                        const std::vector<LoadedPair>& pairs) {
  if (o.method == "icp") {
    IcpOptions icp;
    icp.sift = o.locate.sift;
    icp.match = o.locate.match;
    return LocateObjectIcp(model, calibration, pairs, icp);
  }
  return LocateObject(model, calibration, pairs, o.locate);
}

nlohmann::json GeoJson(const PlacedObject& placed, double time_s) {
  return {{"lat", placed.position.lat},
          {"lon", placed.position.lon},
          {"depth_m", placed.depth_m},
          {"heading_deg", placed.heading_deg},
          {"time_s", time_s}};
}

// Sightings closer than this (horizontally) to a group's mean are the same
// object: a modelled structure is metres across, two of them are not closer.
constexpr double kSameObjectM = 1.0;

struct ObjectGroup {
  std::vector<const StereoSighting*> sightings;
  double east_m = 0, north_m = 0, depth_m = 0, heading_deg = 0;

  void Update() {
    double e = 0, n = 0, d = 0, c = 0, s = 0;
    for (const StereoSighting* x : sightings) {
      e += x->placed->local.east, n += x->placed->local.north, d += x->placed->depth_m;
      c += std::cos(x->placed->heading_deg * M_PI / 180), s += std::sin(x->placed->heading_deg * M_PI / 180);
    }
    const double k = static_cast<double>(sightings.size());
    east_m = e / k, north_m = n / k, depth_m = d / k;
    heading_deg = std::fmod(std::atan2(s, c) * 180 / M_PI + 360, 360.0);
  }
};

// The found sightings grouped into objects, in the order first seen.
std::vector<ObjectGroup> GroupSightings(const std::vector<StereoSighting>& sightings) {
  std::vector<ObjectGroup> groups;
  for (const StereoSighting& s : sightings) {
    if (!s.placed) continue;
    ObjectGroup* nearest = nullptr;
    double best = kSameObjectM;
    for (ObjectGroup& g : groups) {
      const double d = std::hypot(s.placed->local.east - g.east_m, s.placed->local.north - g.north_m);
      if (d < best) best = d, nearest = &g;
    }
    if (!nearest) nearest = &groups.emplace_back();
    nearest->sightings.push_back(&s);
    nearest->Update();
  }
  return groups;
}

// An object's horizontal uncertainty (1 sigma): how far its sightings lie from
// their mean (the trajectory's error between the passes, RMS) and the stereo's
// own (point_sigma_m, RMS over the sightings), in quadrature. One sighting has
// no spread: its sigma is the stereo's alone.
double GroupSigma(const ObjectGroup& g) {
  double spread2 = 0, stereo2 = 0;
  for (const StereoSighting* s : g.sightings) {
    spread2 += std::pow(s->placed->local.east - g.east_m, 2) + std::pow(s->placed->local.north - g.north_m, 2);
    stereo2 += std::pow(s->result.point_sigma_m, 2);
  }
  return std::sqrt((spread2 + stereo2) / static_cast<double>(g.sightings.size()));
}

}  // namespace

void StereoLocateOptions::Check() const {
  feature_enhance.Check();
  if (views < 1) throw InputError("", 0, "--views", "expected a positive number of pairs");
  if (method != "features" && method != "icp") throw InputError("", 0, "--method", "expected features or icp");
  if (time_s && !nav_path && !map_path)
    throw InputError("", 0, "--time", "needs a trajectory: --nav FILE, or --map MAP (the mission's own)");
  if (pair_times_path && time_s)
    throw InputError("", 0, "--pair-times", "and --time: give one (--time places the first pair used)");
  if (pair_times_path && !Dive())
    throw InputError("", 0, "--pair-times", "needs a trajectory to read the pairs' poses on: --nav FILE or --map MAP");
  if (Dive() && views != 1)
    throw InputError("", 0, "--views",
                     "a dive (--nav or --map without --time) locates every pair on its own; give --time T to "
                     "locate the first N pairs jointly");
  if (Dive() && !locate.motion.world_from_camera.empty())
    throw InputError("", 0, "--motion", "a dive's poses come from the trajectory; --motion goes with --time");
}

// What the vehicle's poses come from, about the mission's origin when there is a map.
struct StereoLocate::Trajectory {
  std::optional<NavSeries> series;
  std::optional<LocalFrame> frame;
  std::string text;   // "navigation nav.csv" / "the mission's refined trajectory (m.mbtiles)"
  std::string where;  // file to name in errors
};

std::unique_ptr<StereoLocate::Trajectory> StereoLocate::OpenTrajectory() {
  const StereoLocateOptions& o = options_;
  store_ = o.map_path ? OpenExistingMap(*o.map_path, /*writable=*/true) : nullptr;
  // The mission's origin: the navigation's local frame, and so the detection's position_m, is the mission's.
  const std::optional<LatLon> origin =
      store_ ? std::optional<LatLon>(RequireMissionOrigin(ReadMissionMetadata(*store_), *o.map_path)) : std::nullopt;
  auto t = std::make_unique<Trajectory>();
  if (o.nav_path) {
    NavReadOptions nav_options;
    nav_options.origin = origin;
    const NavTable nav = ReadNavigation(*o.nav_path, nav_options);
    if (!nav.has_times) throw InputError(*o.nav_path, 0, "time_s", "the navigation has no times to place the pairs at");
    // Sorted by time, as build places its frames: unsorted navigation gives the same pose.
    t->series.emplace(nav.records);
    t->frame.emplace(nav.origin);
    t->text = "navigation " + *o.nav_path;
    t->where = *o.nav_path;
  } else if (store_) {
    const MissionTrajectory mission = MissionTrajectory::Read(*store_);
    t->frame.emplace(*origin);
    t->series.emplace(MissionTrajectorySeries(mission, *t->frame, *o.map_path));
    t->text = std::string("the mission's ") +
              (mission.placed() == TrajectorySource::kNav ? "navigation" : TrajectorySourceName(mission.placed())) +
              " trajectory (" + *o.map_path + ")";
    t->where = *o.map_path;
  }
  return t;
}

StereoLocate::StereoLocate(StereoLocateOptions options) : options_(std::move(options)) {}

StereoLocation StereoLocate::Run() {
  const StereoLocateOptions& o = options_;
  o.Check();
  const auto [calibration, model] = LoadRig(o);
  const std::vector<LoadedPair> pairs = LoadPairs(o, calibration);

  // Where the vehicle was, before the (slow) search: bad navigation is reported first.
  const std::unique_ptr<Trajectory> trajectory = OpenTrajectory();
  std::optional<std::pair<VehiclePose, LocalFrame>> vehicle;
  if (o.time_s) {
    const NavSeries& series = *trajectory->series;
    const std::optional<VehiclePose> pose = series.PoseAt(*o.time_s);
    if (!pose)
      throw InputError(trajectory->where, 0, "--time",
                       cv::format("%.3f s is outside the %s times (%.3f to %.3f s)", *o.time_s,
                                  o.nav_path ? "navigation's" : "mission's trajectory's", series.first_time_s(),
                                  series.last_time_s()));
    vehicle.emplace(*pose, *trajectory->frame);
  }

  const nlohmann::json enhancement = ChooseEnhancement(pairs, calibration);
  StereoLocation located;
  located.model_name = model.name;
  located.result = LocateWith(o, model, calibration, pairs);
  nlohmann::json pose_json = LocateResultToJson(located.result, model.name);
  if (!enhancement.is_null()) pose_json["feature_enhance"] = enhancement;
  if (located.result.found && vehicle) {
    located.placed = PlaceObject(located.result.object_from_camera, o.mount, vehicle->first, vehicle->second);
    pose_json["geo"] = GeoJson(*located.placed, *o.time_s);
  }
  WriteJson(o.out, pose_json);
  return located;
}

long long StereoLocate::StoreDetection(const StereoLocation& location) {
  if (!store_ || !location.placed) throw std::logic_error("StoreDetection: no map, or nothing placed in it");
  Detection d = SightingDetection(*location.placed, *options_.time_s);
  d.class_name = location.model_name;
  // Located again within 10 cm (same model file): the same detection, its review kept.
  d = PublishFound(*store_, {d}, d.model, {d.class_name})[0];
  store_->Flush();
  return static_cast<long long>(d.id);
}

StereoDive StereoLocate::RunDive() {
  const StereoLocateOptions& o = options_;
  o.Check();
  if (!o.Dive()) throw std::logic_error("RunDive: not a dive (--time given, or no trajectory)");
  const auto [calibration, model] = LoadRig(o);
  const std::vector<PairFiles> files = ListStereoPairs(o.pairs_dir);
  // Every pair's time before the (slow) search: a pair without one is bad input.
  StereoDive dive;
  dive.sightings = TimedSightings(o, files);
  const std::unique_ptr<Trajectory> trajectory = OpenTrajectory();
  const NavSeries& series = *trajectory->series;
  dive.model_name = model.name;
  dive.trajectory = trajectory->text;
  for (StereoSighting& s : dive.sightings)
    if (!series.PoseAt(*s.time_s))
      s.skipped = cv::format("at %.3f s, outside the trajectory's times (%.3f to %.3f s)", *s.time_s,
                             series.first_time_s(), series.last_time_s());

  nlohmann::json enhancement;
  if (o.feature_enhance.spec != "off") {  // probed on the first pairs the dive searches
    std::vector<LoadedPair> probe;
    for (size_t i = 0; i < files.size() && static_cast<int>(probe.size()) * 2 < o.feature_enhance.probe_frames; ++i)
      if (dive.sightings[i].skipped.empty())
        probe.push_back(LoadStereoPair(files[i], calibration.image_size, o.calib_path));
    enhancement = ChooseEnhancement(probe, calibration);
  }

  ProgressBar progress("pairs", static_cast<long>(files.size()), !o.quiet);
  nlohmann::json sightings = nlohmann::json::array();
  for (size_t i = 0; i < files.size(); ++i) {
    StereoSighting& s = dive.sightings[i];
    nlohmann::json j;
    if (s.skipped.empty()) {
      // One pair in memory at a time: a dive may hold thousands.
      const std::vector<LoadedPair> pair = {LoadStereoPair(files[i], calibration.image_size, o.calib_path)};
      s.result = LocateWith(o, model, calibration, pair);
      j = LocateResultToJson(s.result, model.name);
      if (s.result.found) {
        s.placed = PlaceObject(s.result.object_from_camera, o.mount, *series.PoseAt(*s.time_s), *trajectory->frame);
        j["geo"] = GeoJson(*s.placed, *s.time_s);
        j["geo"]["position_m"] = {s.placed->local.east, s.placed->local.north};
      }
    } else {
      j = {{"found", false}, {"skipped", s.skipped}};
    }
    j["pair"] = s.pair;
    j["time_s"] = *s.time_s;
    j["time_from"] = s.time_from;
    sightings.push_back(std::move(j));
    progress.Update(static_cast<long>(i + 1));
  }
  progress.Finish();

  // The summary: how many were found, and how well the found ones agree (per object).
  int found = 0, skipped = 0;
  for (const StereoSighting& s : dive.sightings) found += s.placed.has_value(), skipped += !s.skipped.empty();
  nlohmann::json objects = nlohmann::json::array();
  const LocalFrame& frame = *trajectory->frame;
  for (const ObjectGroup& g : GroupSightings(dive.sightings)) {
    double sum2 = 0, worst = 0, depth2 = 0, sigma2 = 0;
    nlohmann::json pairs = nlohmann::json::array();
    for (const StereoSighting* s : g.sightings) {
      const double d = std::hypot(s->placed->local.east - g.east_m, s->placed->local.north - g.north_m);
      sum2 += d * d, worst = std::max(worst, d);
      depth2 += std::pow(s->placed->depth_m - g.depth_m, 2);
      sigma2 += std::pow(s->result.point_sigma_m, 2);
      pairs.push_back(s->pair);
    }
    const double k = static_cast<double>(g.sightings.size());
    const LatLon at = frame.ToLatLon({g.east_m, g.north_m});
    objects.push_back({{"sightings", g.sightings.size()},
                       {"pairs", pairs},
                       {"lat", at.lat},
                       {"lon", at.lon},
                       {"position_m", {g.east_m, g.north_m}},
                       {"depth_m", g.depth_m},
                       {"heading_deg", g.heading_deg},
                       // How far the sightings lie from their mean: the trajectory's error between the
                       // passes plus the stereo's (point_sigma_m, RMS over the sightings, for comparison).
                       {"spread_rms_m", std::sqrt(sum2 / k)},
                       {"spread_max_m", worst},
                       {"depth_spread_rms_m", std::sqrt(depth2 / k)},
                       {"stereo_sigma_rms_m", std::sqrt(sigma2 / k)}});
  }
  dive.summary = {{"pairs", files.size()},
                  {"found", found},
                  {"not_found", static_cast<int>(files.size()) - found - skipped},
                  {"skipped", skipped},
                  {"objects", objects}};
  nlohmann::json out = {{"format", "seamap-stereo-sightings"},
                        {"model", model.name},
                        {"trajectory", trajectory->text},
                        {"sightings", sightings},
                        {"summary", dive.summary}};
  if (!enhancement.is_null()) out["feature_enhance"] = enhancement;
  WriteJson(o.out, out);
  return dive;
}

nlohmann::json StereoLocate::ChooseEnhancement(const std::vector<LoadedPair>& probe,
                                               const StereoCalibration& calibration) {
  const FeatureEnhanceOptions& o = options_.feature_enhance;
  if (o.spec == "off") return nullptr;
  SiftOptions& sift = options_.locate.sift;
  const EnhancementChoice choice = ChooseStereoEnhancement(o, probe, calibration, sift, options_.locate.match);
  sift.enhance = choice.chain;
  nlohmann::json trials = nlohmann::json::array();
  std::fprintf(stderr, "feature enhancement (%s): %s\n", o.spec.c_str(), choice.chain.Names().c_str());
  for (const EnhancementTrial& t : choice.trials) {
    std::fprintf(stderr, "  %-40s %7.1f stereo inliers/pair %7.1f features/image\n", t.chain.c_str(), t.inliers,
                 t.features);
    trials.push_back({{"chain", t.chain}, {"inliers_per_pair", t.inliers}, {"features_per_image", t.features}});
  }
  return {{"requested", o.spec}, {"chain", choice.chain.Names()}, {"trials", trials}};
}

std::vector<long long> StereoLocate::StoreDetections(const StereoDive& dive) {
  if (!store_) throw std::logic_error("StoreDetections: no map");
  const LocalFrame frame(RequireMissionOrigin(ReadMissionMetadata(*store_), *options_.map_path));
  std::vector<Detection> found = StereoObjectDetections(options_, dive.sightings, dive.model_name, frame);
  std::vector<long long> ids;
  if (found.empty()) return ids;
  const std::string model = found.front().model;
  // This model's earlier unreviewed locations are replaced; one found again within 10 cm keeps its id and review.
  for (const Detection& d : PublishFound(*store_, std::move(found), model, {dive.model_name}))
    ids.push_back(static_cast<long long>(d.id));
  store_->Flush();
  return ids;
}

Detection StereoLocate::SightingDetection(const PlacedObject& placed, double time_s) const {
  return StereoSightingDetection(options_, placed, time_s);
}

std::pair<StereoCalibration, ObjectModel> LoadStereoRig(const StereoLocateOptions& options) {
  return LoadRig(options);
}

LocateResult LocateStereoPairs(const StereoLocateOptions& options, const ObjectModel& model,
                               const StereoCalibration& calibration, const std::vector<LoadedPair>& pairs) {
  return LocateWith(options, model, calibration, pairs);
}

std::vector<StereoSighting> TimedSightings(const StereoLocateOptions& o, const std::vector<PairFiles>& files) {
  const std::optional<PairTimes> table =
      o.pair_times_path ? std::optional<PairTimes>(PairTimes::Read(*o.pair_times_path)) : std::nullopt;
  std::vector<StereoSighting> sightings;
  for (const PairFiles& f : files) {
    StereoSighting s;
    s.pair = f.name;
    if (table) {
      s.time_s = table->Find(f.name, f.left, f.right);
      s.time_from = "--pair-times";
      if (!s.time_s)
        throw InputError(*o.pair_times_path, 0, "image",
                         "has no time for pair '" + Shorten(f.name, 100) + "' (" + f.left + ")");
    } else {
      s.time_s = PairTimeFromName(f.name);
      s.time_from = "name";
      if (!s.time_s)
        throw InputError(f.left, 0, "--pair-times",
                         "pair '" + Shorten(f.name, 100) +
                             "' has no time in its name (a UTC stamp YYYYMMDD_HHMMSS[_mmm], or seconds as t12.5, "
                             "12.5s or NAME_12.500): give --pair-times FILE (image,time_s), or --time T, to place it "
                             "on the trajectory (" +
                             (o.nav_path ? "--nav" : "--map") + ")");
    }
    sightings.push_back(std::move(s));
  }
  return sightings;
}

std::vector<Detection> StereoObjectDetections(const StereoLocateOptions& options,
                                              const std::vector<StereoSighting>& sightings,
                                              const std::string& model_name, const LocalFrame& frame) {
  std::vector<Detection> found;
  for (const ObjectGroup& g : GroupSightings(sightings)) {
    PlacedObject placed;
    placed.local = {g.east_m, g.north_m};
    placed.position = frame.ToLatLon(placed.local);
    placed.depth_m = g.depth_m;
    placed.heading_deg = g.heading_deg;
    found.push_back(StereoSightingDetection(options, placed, *g.sightings.front()->time_s, GroupSigma(g)));
    found.back().class_name = model_name;
  }
  return found;
}

Detection StereoSightingDetection(const StereoLocateOptions& options, const PlacedObject& placed, double time_s,
                                  std::optional<double> sigma_m) {
  Detection d;
  d.source = "stereo";
  d.model = std::filesystem::path(options.model_path).filename().string();
  d.score = 1;
  d.position = placed.position;
  d.position_m = std::array<double, 2>{placed.local.east, placed.local.north};  // the mission's frame
  d.heading_deg = placed.heading_deg;
  d.depth_m = placed.depth_m;
  d.sigma_m = sigma_m;
  d.time_s = time_s;
  d.status = "unconfirmed";
  return d;
}

}  // namespace seamap
