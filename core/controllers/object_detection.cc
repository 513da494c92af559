#include "core/controllers/object_detection.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#include <opencv2/core.hpp>

#include "core/detect/detection_record.h"
#include "core/detect/yolo_model.h"
#include "core/mission/mission_metadata.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap {
namespace {

int MetaInt(const std::map<std::string, std::string>& meta, const std::string& key, const std::string& map) {
  try {
    return std::stoi(meta.at(key));
  } catch (const std::exception&) {
    throw InputError(map, 0, key, "the map's metadata has no valid '" + key + "'");
  }
}

// One net per thread (a cv::dnn::Net must not run two forwards at once);
// windows dealt round-robin; the merge does not depend on who searched what.
std::vector<std::unique_ptr<WindowSearcher>> SearchWindows(const DetectSettings& settings, const TileStore& tiles,
                                                           const std::vector<WindowKey>& windows, int threads,
                                                           bool quiet) {
  std::vector<std::unique_ptr<WindowSearcher>> searchers;
  for (int i = 0; i < threads; ++i) searchers.push_back(std::make_unique<WindowSearcher>(settings));
  const TileReader read = StoreReader(tiles, settings.stored_zoom);
  ProgressBar progress("windows", static_cast<long>(windows.size()), !quiet);
  std::atomic<long> done{0};
  std::mutex progress_mutex;
  std::vector<std::thread> pool;
  std::exception_ptr error;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      try {
        for (size_t i = t; i < windows.size(); i += threads) {
          searchers[t]->Search(windows[i], read);
          std::lock_guard<std::mutex> lock(progress_mutex);
          progress.Update(++done);
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        if (!error) error = std::current_exception();
      }
    });
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
  progress.Finish();
  return searchers;
}

}  // namespace

void ObjectDetectionOptions::Check() const {
  if (threads < 1 || threads > 64) throw InputError("--threads", 0, "", "expected 1..64");
  if (layer != "raw" && layer != "enhanced")
    throw InputError("--layer", 0, "", "expected raw or enhanced, got '" + layer + "'");
}

ObjectDetectionResult DetectObjects(const ObjectDetectionOptions& options) {
  options.Check();
  const std::string& path = options.map_path;
  const std::string& layer = options.layer;
  // The model first: a bad model is reported before the map is opened.
  const auto model = YoloModel::Inspect(options.model_path, options.classes_path);

  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path, 0, "", "no such map");
  std::unique_ptr<TileStore> store = OpenExistingMap(path, /*writable=*/true);
  const auto meta = store->Metadata();
  const MissionMetadata mission = ReadMissionMetadata(meta);
  const std::vector<std::string> layers = mission.LayersOrRaw();
  if (std::find(layers.begin(), layers.end(), layer) == layers.end()) {
    std::string list;
    for (const auto& l : layers) list += (list.empty() ? "" : ", ") + l;
    throw InputError("--layer", 0, "", "the map has no " + layer + " layer (it has: " + list + ")");
  }
  std::unique_ptr<TileStore> layer_store = layer == layers[0] ? nullptr : store->OpenLayer(layer);
  const TileStore& tiles = layer_store ? *layer_store : *store;
  if (!model->layer.empty() && model->layer != layer)
    std::fprintf(stderr, "warning: %s was trained on the %s layer; searching the %s layer\n",
                 options.model_path.c_str(), model->layer.c_str(), layer.c_str());

  DetectSettings settings;
  settings.model = model;
  settings.min_score = options.min_score.value_or(model->min_score);
  if (!options.min_score) settings.class_min_scores = model->class_min_scores;  // --min-score: one for all
  settings.keep_cut_views = options.keep_cut_views;
  if (mission.unreadable.count(kTileSizeKey))
    throw InputError(path, 0, kTileSizeKey, std::string("the map's metadata has no valid '") + kTileSizeKey + "'");
  settings.tile_size = mission.tile_size_px.value_or(256);
  const int min_zoom = MetaInt(meta, "minzoom", path), base_zoom = MetaInt(meta, "maxzoom", path);
  settings.origin = RequireMissionOrigin(mission, path);
  settings.zooms =
      ChooseZooms(options.zooms, "--zooms", min_zoom, base_zoom, settings.origin.lat, settings.tile_size, *model);
  settings.stored_zoom = base_zoom;

  cv::setNumThreads(1);  // as in a build: ms per window on one thread
  const std::vector<WindowKey> windows = MapWindows(tiles, settings.zooms, settings.tile_size, settings.stored_zoom);
  std::string zoom_text;
  for (int z : settings.zooms) zoom_text += (zoom_text.empty() ? "" : ",") + std::to_string(z);
  std::fprintf(stderr, "seamap detect: %s (%s, %s layout, %zu classes) on %s layer %s, zooms %s: %zu windows\n",
               model->name.c_str(), options.model_path.c_str(), YoloLayoutName(model->layout),
               model->class_names.size(), path.c_str(), layer.c_str(), zoom_text.c_str(), windows.size());
  const auto searchers = SearchWindows(settings, tiles, windows, options.threads, options.quiet);
  std::vector<RawDetection> raw;
  ObjectDetectionResult result;
  for (const auto& sr : searchers) {
    const auto r = sr->Raw();
    raw.insert(raw.end(), r.begin(), r.end());
    result.stats.Add(sr->stats());
  }
  result.objects = MergeSearched(settings, std::move(raw), store->Records().Frames());
  StoreRecognised(*store, result.objects, model->name, model->class_names);
  store->Flush();
  return result;
}

}  // namespace seamap
