#pragma once
// What `seamap detect`, `build --detect` and `replay --detect` share: the
// shipped model's path, reading --zooms, and reporting what was found.
#include <optional>
#include <string>
#include <vector>

#include "cli/args.h"
#include "core/detect/detection_run.h"
#include "core/detect/live_detector.h"
#include "core/mosaic/mosaic_plan.h"

namespace seamap::cli {

// data/models/seabed_objects.onnx of this checkout (SEAMAP_DATA_DIR overrides the data folder).
std::string DefaultModelPath();

// "22,20,18" -> zooms; InputError naming `option` when malformed.
std::vector<int> ParseZooms(const std::string& text, const std::string& option);

// --min-score in [0.001, 1] (nullopt: not given, the model's own applies);
// InputError naming it otherwise.
std::optional<float> MinScoreArg(Args& args);

// Counts per class and ms per window (median, p90) on stdout.
void PrintDetectSummary(const std::vector<RecognisedObject>& objects, const DetectStats& stats,
                        const std::string& prefix);

// Writes the objects as GeoJSON; InputError naming `option` when it cannot.
void WriteGeoJson(const std::vector<RecognisedObject>& objects, const std::string& path, const std::string& option);

// --detect [--detect-model FILE]: the model, checked now (before the map is
// opened); null without --detect. The caller lists both among its options.
std::shared_ptr<const YoloModelInfo> LiveDetectArgs(Args& args);

// The recogniser of a build: searches the main layer's finished tiles at
// the config's detect.zooms ({"detect": {"zooms": [25, 23]}}, InputError
// naming config_source and the key when malformed), else the default zooms.
std::unique_ptr<LiveDetector> StartLiveDetector(std::shared_ptr<const YoloModelInfo> model, const MosaicPlan& plan,
                                                int tile_size, LatLon origin, const TileStore* store,
                                                const std::optional<nlohmann::json>& detect_config,
                                                const std::string& config_source);

// After the builder's Finish: drains the detector, stores its objects in
// the mission (replacing the recogniser's earlier ones), prints the summary.
// `publish`: where the final objects go instead of straight into the store
// (replay: through the server's registry, so the console hears of them).
void FinishLiveDetector(LiveDetector& detector, TileStore& store, const LiveDetector::Found& publish = nullptr);

}  // namespace seamap::cli
