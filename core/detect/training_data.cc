#include "core/detect/training_data.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/detect/detection_run.h"
#include "core/detect/training_windows.h"
#include "core/detect/yolo_model.h"
#include "core/mission/mission_classes.h"
#include "core/mission/mission_metadata.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap {
namespace {
namespace fs = std::filesystem;

struct Mission {
  std::string path, name, model;
  std::unique_ptr<TileStore> store;
  int tile_size = 256;
  std::vector<int> zooms;
  int stored_zoom = kMaxStoredZoom;  // the map's finest (levels above it are scaled up)
  TrainingPlan plan;
};

// A file-name-safe mission name from the map's file name, unique among `taken`.
std::string MissionName(const std::string& path, const std::vector<Mission>& taken) {
  std::string stem = fs::path(path).stem().string();
  if (stem.empty()) stem = "mission";
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-') c = '_';
  stem = stem.substr(0, 64);
  std::string name = stem;
  for (int k = 2; std::any_of(taken.begin(), taken.end(), [&](const Mission& m) { return m.name == name; }); ++k)
    name = stem + "_" + std::to_string(k);
  return name;
}

int MetaInt(const std::map<std::string, std::string>& meta, const std::string& key, const std::string& map) {
  try {
    return std::stoi(meta.at(key));
  } catch (const std::exception&) {
    throw InputError(map, 0, key, "the map's metadata has no valid '" + key + "'");
  }
}

nlohmann::json BoxJson(const WindowBox& b, bool with_source) {
  nlohmann::json j = {{"class", b.class_name}, {"box_px", b.box_px}, {"id", b.id}};
  if (with_source) j["source"] = b.source;
  return j;
}

}  // namespace

void TrainingDataOptions::Check() const {
  if (maps.empty()) throw InputError("", 0, "MAP", "expected at least one reviewed map");
  if (out_dir.empty()) throw InputError("", 0, "--out", "is required: the folder to write the windows to");
  if (!(empty_per_labelled >= 0 && empty_per_labelled <= 20))
    throw InputError("", 0, "--empty", "expected 0-20 empty windows per window with a label or a negative");
}

TrainingDataSummary WriteTrainingData(const TrainingDataOptions& options) {
  options.Check();
  const fs::path out(options.out_dir);
  std::error_code ec;
  if (fs::exists(out, ec) && !options.overwrite)
    throw InputError(options.out_dir, 0, "--out",
                     "exists; pass --overwrite to replace its images/, labels/ and manifest.json");
  if (fs::exists(out, ec) && !fs::is_directory(out, ec))
    throw InputError(options.out_dir, 0, "--out", "exists and is not a folder");
  const auto model = YoloModel::Inspect(options.model_path, "");

  // Every map is read and planned before anything is written.
  TrainingDataSummary summary;
  summary.classes = model->class_names;
  std::vector<Mission> missions;
  for (const std::string& path : options.maps) {
    if (!fs::exists(path, ec)) throw InputError(path, 0, "MAP", "no such map");
    if (!fs::is_directory(path, ec) && fs::path(path).extension() != ".mbtiles")
      throw InputError(path, 0, "MAP", "not a map: expected a .mbtiles file or a map folder");
    Mission m;
    m.path = path;
    m.name = MissionName(path, missions);
    m.store = OpenExistingMap(path, /*writable=*/false);
    const auto meta = m.store->Metadata();
    const MissionMetadata mission = ReadMissionMetadata(meta);
    m.tile_size = mission.tile_size_px.value_or(256);
    const LatLon origin = RequireMissionOrigin(mission, path);
    m.zooms = ChooseZooms(options.zooms, "--zooms", MetaInt(meta, "minzoom", path), MetaInt(meta, "maxzoom", path),
                          origin.lat, m.tile_size, *model);
    m.stored_zoom = MetaInt(meta, "maxzoom", path);
    std::vector<int64_t> unreadable;
    std::vector<Detection> detections = m.store->Records().ReadableDetections(&unreadable);
    for (Detection& d : detections) NormaliseDetection(&d);
    std::map<std::string, int> models;
    for (const Detection& d : detections)
      if (d.source == "recogniser") ++models[d.model];
    for (const auto& [name, count] : models)
      if (m.model.empty() || count > models[m.model]) m.model = name;
    TrainingPlanOptions plan_options;
    plan_options.zooms = m.zooms;
    plan_options.tile_size = m.tile_size;
    plan_options.empty_per_labelled = options.empty_per_labelled;
    plan_options.seed = options.seed;
    const TileReader read = StoreReader(*m.store, m.stored_zoom);
    const auto painted = [&](const WindowKey& w) {
      double fraction = 0;
      ComposeWindow(w, m.tile_size, read, &fraction);
      return fraction;
    };
    m.plan = PlanTrainingWindows(detections, plan_options, MapWindows(*m.store, m.zooms, m.tile_size, m.stored_zoom),
                                 painted);
    if (m.plan.labelled == 0)
      throw InputError(path, 0, "",
                       "no confirmed or rejected detection and no operator mark with a box (" +
                           std::to_string(detections.size()) +
                           " detections): nothing to learn from; review the mission in the console first "
                           "(confirm, reject, draw boxes for missed objects)");
    for (const Detection& d : detections)
      if (RoleOf(d) == TrainingRole::kLabel) ExtendClassTable(&summary.classes, {d.class_name});
    missions.push_back(std::move(m));
  }

  fs::create_directories(out / "images");
  fs::create_directories(out / "labels");
  for (const char* sub : {"images", "labels"})
    for (const auto& e : fs::directory_iterator(out / sub)) fs::remove(e.path());
  long total = 0;
  for (const Mission& m : missions) total += static_cast<long>(m.plan.windows.size());
  ProgressBar progress("windows", total, !options.quiet);
  nlohmann::json windows = nlohmann::json::array(), mission_list = nlohmann::json::array();
  for (const Mission& m : missions) {
    mission_list.push_back({{"path", fs::absolute(m.path).string()}, {"name", m.name}, {"model", m.model}});
    const TileReader read = StoreReader(*m.store, m.stored_zoom);
    for (const TrainingWindow& w : m.plan.windows) {
      char stem[128];
      std::snprintf(stem, sizeof stem, "%s_z%d_x%d_y%d", m.name.c_str(), w.key.z, w.key.x, w.key.y);
      const cv::Mat bgr = ComposeTrainingWindow(w, m.tile_size, read);
      const std::string image = std::string("images/") + stem + ".png", label = std::string("labels/") + stem + ".txt";
      if (!cv::imwrite((out / image).string(), bgr)) throw InputError((out / image).string(), 0, "", "cannot write");
      std::ofstream txt(out / label);
      txt << YoloLabelText(w.labels, summary.classes, bgr.cols);
      if (!txt) throw InputError((out / label).string(), 0, "", "cannot write");
      nlohmann::json labels = nlohmann::json::array(), negatives = nlohmann::json::array();
      for (const WindowBox& b : w.labels) {
        labels.push_back(BoxJson(b, true));
        ++summary.per_class[b.class_name];
      }
      for (const WindowBox& b : w.negatives) negatives.push_back(BoxJson(b, false));
      const auto level = std::find(m.zooms.begin(), m.zooms.end(), w.key.z) - m.zooms.begin();
      windows.push_back({{"image", image},
                         {"label", label},
                         {"mission", m.name},
                         {"z", w.key.z},
                         {"x", w.key.x},
                         {"y", w.key.y},
                         {"level", level},
                         {"side_px", bgr.cols},
                         {"labels", labels},
                         {"negatives", negatives},
                         {"masked_px", static_cast<int>(w.masked_px.size())}});
      summary.labels += static_cast<int>(w.labels.size());
      summary.negatives += static_cast<int>(w.negatives.size());
      progress.Update(++summary.windows);
    }
    summary.empty += m.plan.empty;
    summary.skipped += m.plan.skipped_overlap;
    summary.ignored += m.plan.ignored;
  }
  progress.Finish();
  const nlohmann::json manifest = {
      {"missions", mission_list},
      {"classes", summary.classes},
      {"counts",
       {{"windows", summary.windows},
        {"labels", summary.labels},
        {"negatives", summary.negatives},
        {"empty_windows", summary.empty},
        {"per_class", summary.per_class},
        {"ignored_detections", summary.ignored},
        {"skipped_windows", summary.skipped}}},
      {"rules",
       {{"labels", "confirmed recogniser detections and operator marks with a box, by their class"},
        {"negatives", "rejected recogniser detections: their windows are written, their boxes are no label"},
        {"unconfirmed",
         "unconfirmed detections, stereo sightings and labels less than half inside a window are no labels: "
         "painted grey 114 in the window (masked_px counts them); a window where one overlaps a label, or "
         "holding an operator's point mark, is left out (skipped_windows)"},
        {"empty", "windows of the same levels touching no detection, a seeded sample (--empty per labelled window)"},
        {"levels", "the recogniser's zooms; level 0 is the finest"}}},
      {"windows", windows}};
  std::ofstream json(out / "manifest.json");
  json << manifest.dump(1) << "\n";
  if (!json) throw InputError((out / "manifest.json").string(), 0, "", "cannot write");
  return summary;
}

}  // namespace seamap
