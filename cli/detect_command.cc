// seamap detect: the recogniser on a finished map (spec detections-on-tiles).
#include <atomic>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <thread>

#include <opencv2/core.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/detect_setup.h"
#include "core/detect/detection_record.h"
#include "core/mission/mission_metadata.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap::cli {
namespace {

const char* kHelp =
    "usage: seamap detect MAP [options]\n"
    "\n"
    "Searches a map's tiles for objects with a YOLO model (ONNX, v5 or v8 layout),\n"
    "stores them in the mission (source \"recogniser\") and prints counts per class.\n"
    "\n"
    "  --model FILE      ONNX model (default: data/models/seabed_objects.onnx)\n"
    "  --classes FILE    class names, one per line (default: the model's metadata)\n"
    "  --zooms LIST      levels to search, e.g. 22,20,18 (default: base, base-2, ...\n"
    "                    until the model's largest class fits)\n"
    "  --min-score S     drop boxes scoring below S (default: the model's\n"
    "                    seamap.min_score metadata, else 0.4)\n"
    "  --layer NAME      raw | enhanced: the tiles searched (default raw)\n"
    "  --out FILE        also write the detections as GeoJSON\n"
    "  --threads N       windows searched at once, one network each (default 1)\n"
    "  --quiet           no progress bar\n";

int MetaInt(const std::map<std::string, std::string>& meta, const std::string& key, const std::string& map) {
  try {
    return std::stoi(meta.at(key));
  } catch (const std::exception&) {
    throw InputError(map, 0, key, "the map's metadata has no valid '" + key + "'");
  }
}

}  // namespace

int RunDetect(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help", "quiet"});
  if (args.Flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  const std::string model_path = args.GetOr("model", DefaultModelPath());
  const std::string classes = args.GetOr("classes", "");
  const std::optional<std::string> zooms_arg = args.Get("zooms");
  const std::optional<std::vector<int>> requested =
      zooms_arg ? std::optional<std::vector<int>>(ParseZooms(*zooms_arg, "--zooms")) : std::nullopt;
  const std::optional<float> min_score = MinScoreArg(args);
  const std::string layer = args.GetOr("layer", "raw");
  const std::optional<std::string> out = args.Get("out");
  const bool quiet = args.Flag("quiet");
  const int threads = args.GetInt("threads", 1);
  args.RejectUnknown();
  if (threads < 1 || threads > 64) throw InputError("--threads", 0, "", "expected 1..64");
  if (args.positionals().size() != 1) {
    std::fputs(kHelp, stderr);
    return 2;
  }
  if (layer != "raw" && layer != "enhanced")
    throw InputError("--layer", 0, "", "expected raw or enhanced, got '" + layer + "'");
  // The model first: a bad model is reported before the map is opened.
  const auto model = YoloModel::Inspect(model_path, classes);

  const std::string path = args.positionals()[0];
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
    std::fprintf(stderr, "warning: %s was trained on the %s layer; searching the %s layer\n", model_path.c_str(),
                 model->layer.c_str(), layer.c_str());

  DetectSettings settings;
  settings.model = model;
  settings.min_score = min_score.value_or(model->min_score);
  if (mission.unreadable.count(kTileSizeKey))
    throw InputError(path, 0, kTileSizeKey, std::string("the map's metadata has no valid '") + kTileSizeKey + "'");
  settings.tile_size = mission.tile_size_px.value_or(256);
  const int min_zoom = MetaInt(meta, "minzoom", path), base_zoom = MetaInt(meta, "maxzoom", path);
  settings.origin = RequireMissionOrigin(mission, path);
  settings.zooms =
      ChooseZooms(requested, "--zooms", min_zoom, base_zoom, settings.origin.lat, settings.tile_size, *model);

  cv::setNumThreads(1);  // as in a build: ms per window on one thread
  const std::vector<WindowKey> windows = MapWindows(tiles, settings.zooms, settings.tile_size);
  std::string zoom_text;
  for (int z : settings.zooms) zoom_text += (zoom_text.empty() ? "" : ",") + std::to_string(z);
  std::fprintf(stderr, "seamap detect: %s (%s, %s layout, %zu classes) on %s layer %s, zooms %s: %zu windows\n",
               model->name.c_str(), model_path.c_str(), YoloLayoutName(model->layout), model->class_names.size(),
               path.c_str(), layer.c_str(), zoom_text.c_str(), windows.size());
  // One net per thread (a cv::dnn::Net must not run two forwards at once);
  // windows dealt round-robin; the merge does not depend on who searched what.
  std::vector<std::unique_ptr<WindowSearcher>> searchers;
  for (int i = 0; i < threads; ++i) searchers.push_back(std::make_unique<WindowSearcher>(settings));
  const TileReader read = StoreReader(tiles);
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
  std::vector<RawDetection> raw;
  DetectStats stats;
  for (const auto& sr : searchers) {
    const auto r = sr->Raw();
    raw.insert(raw.end(), r.begin(), r.end());
    stats.searched += sr->stats().searched;
    stats.skipped += sr->stats().skipped;
    stats.window_ms.insert(stats.window_ms.end(), sr->stats().window_ms.begin(), sr->stats().window_ms.end());
  }
  const std::vector<RecognisedObject> objects = MergeSearched(settings, std::move(raw), store->Records().Frames());
  StoreRecognised(*store, objects, model->name, model->class_names);
  store->Flush();
  if (out) WriteGeoJson(objects, *out, "--out");
  PrintDetectSummary(objects, stats, "");
  return 0;
}

}  // namespace seamap::cli
