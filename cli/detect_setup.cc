#include "cli/detect_setup.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "core/detect/detection_record.h"
#include "core/detect/onnx_meta.h"
#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap::cli {

std::string DefaultModelPath() {
  const char* env = std::getenv("SEAMAP_DATA_DIR");
  return std::string(env ? env : SEAMAP_DATA_DIR) + "/models/seabed_objects.onnx";
}

std::vector<int> ParseZooms(const std::string& text, const std::string& option) {
  std::vector<int> zooms;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    size_t used = 0;
    int z = -1;
    try {
      z = std::stoi(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != item.size() || item.empty() || z < 0 || z > 30)
      throw InputError(option, 0, "", "expected zooms 0..30 separated by commas (e.g. 22,20,18), got '" + text + "'");
    zooms.push_back(z);
  }
  if (zooms.empty()) throw InputError(option, 0, "", "expected at least one zoom");
  return zooms;
}

std::optional<float> MinScoreArg(Args& args) {
  const std::optional<std::string> text = args.Get("min-score");
  if (!text) return std::nullopt;
  const double s = args.GetDouble("min-score", 0);
  if (!(s >= kMinScoreFloor && s <= 1))
    throw InputError(
        "--min-score", 0, "",
        "expected a score between 0.001 and 1 (a probability the model could mean), got '" + Excerpt(*text) + "'");
  return static_cast<float>(s);
}

void PrintDetectSummary(const std::vector<RecognisedObject>& objects, const DetectStats& stats,
                        const std::string& prefix) {
  std::map<std::string, int> counts;
  for (const RecognisedObject& o : objects) ++counts[o.class_name];
  std::printf("%s%zu objects", prefix.c_str(), objects.size());
  const char* sep = " (";
  for (const auto& [name, n] : counts) {
    std::printf("%s%s %d", sep, name.c_str(), n);
    sep = ", ";
  }
  std::printf("%s; %d windows searched, %d empty skipped; %.1f ms per window (median), %.1f (p90)\n",
              counts.empty() ? "" : ")", stats.searched, stats.skipped, Percentile(stats.window_ms, 0.5),
              Percentile(stats.window_ms, 0.9));
  // What the model gave that no map should hold (issue 33): said, never stored.
  if (stats.non_finite > 0)
    std::printf("%swarning: %lld boxes with an inf/NaN coordinate or score dropped (the model's output is broken)\n",
                prefix.c_str(), static_cast<long long>(stats.non_finite));
  if (stats.capped_windows > 0)
    std::printf(
        "%swarning: %d windows proposed more boxes than %d before NMS or %d after it; %lld lowest scores "
        "dropped (is --min-score too low?)\n",
        prefix.c_str(), stats.capped_windows, kMaxYoloCandidates, kMaxYoloBoxes,
        static_cast<long long>(stats.capped_boxes));
}

void WriteGeoJson(const std::vector<RecognisedObject>& objects, const std::string& path, const std::string& option) {
  std::ofstream out(path);
  if (!out) throw InputError(path, 0, option, "cannot write the GeoJSON file");
  out << RecognisedFeatureCollection(objects).dump(1) << "\n";
  if (!out) throw InputError(path, 0, option, "cannot write the GeoJSON file");
}

}  // namespace seamap::cli

namespace seamap::cli {

std::shared_ptr<const YoloModelInfo> LiveDetectArgs(Args& args) {
  const std::optional<std::string> model = args.Get("detect-model");
  if (!args.Flag("detect")) {
    if (model) throw InputError("--detect-model", 0, "", "needs --detect");
    return nullptr;
  }
  return YoloModel::Inspect(model ? *model : DefaultModelPath(), "");
}

std::unique_ptr<LiveDetector> StartLiveDetector(std::shared_ptr<const YoloModelInfo> model, const MosaicPlan& plan,
                                                int tile_size, LatLon origin, const TileStore* store,
                                                const std::optional<nlohmann::json>& detect_config,
                                                const std::string& config_source) {
  std::optional<std::vector<int>> zooms;
  if (detect_config) {
    const auto bad = [&](const std::string& key, const std::string& what) {
      return InputError(config_source, 0, key, what);
    };
    if (!detect_config->is_object()) throw bad("detect", "expected an object {\"zooms\": [25, 23]}");
    for (const auto& [key, v] : detect_config->items()) {
      if (key != "zooms") throw bad("detect." + key, "unknown key (expected zooms)");
      if (!v.is_array() || v.empty()) throw bad("detect.zooms", "expected a list of zooms, e.g. [25, 23]");
      zooms.emplace();
      for (const auto& z : v) {
        if (!z.is_number_integer()) throw bad("detect.zooms", "expected a list of zooms, e.g. [25, 23]");
        zooms->push_back(z.get<int>());
      }
    }
  }
  DetectSettings s;
  s.model = model;
  s.min_score = model->min_score;
  s.class_min_scores = model->class_min_scores;
  s.tile_size = tile_size;
  s.origin = origin;
  s.zooms = ChooseZooms(zooms, config_source + " detect.zooms", plan.min_zoom, plan.base_zoom, plan.latitude, tile_size,
                        *model);
  s.stored_zoom = plan.base_zoom;
  std::string zoom_text;
  for (int z : s.zooms) zoom_text += (zoom_text.empty() ? "" : ",") + std::to_string(z);
  std::fprintf(stderr, "detect: %s (%s layout, %zu classes), zooms %s\n", model->name.c_str(),
               YoloLayoutName(model->layout), model->class_names.size(), zoom_text.c_str());
  return std::make_unique<LiveDetector>(s, store);
}

void FinishLiveDetector(LiveDetector& detector, TileStore& store, const LiveDetector::Found& publish) {
  const std::vector<RecognisedObject> objects = detector.Finish(store.Records().Frames());
  if (publish)
    publish(objects);
  else
    StoreRecognised(store, objects, detector.model().name, detector.model().class_names);
  store.Flush();
  std::printf("detect: backlog peak %d windows, drained in %.2f s after the build\n", detector.backlog_peak(),
              detector.drain_seconds());
  PrintDetectSummary(objects, detector.stats(), "detect: ");
}

}  // namespace seamap::cli
