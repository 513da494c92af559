#pragma once
// A new search of the map meets the detections already in the mission: which
// earlier detection each fresh one continues (spec sect. 8.7). One rule for
// `seamap detect`/`build --detect` and `stereo-locate --map` (StoreFound) and
// for the live replay (server's DetectionRegistry::Publish), so ids, the
// operator's review and notes survive a search the same way in all.
#include <string>
#include <vector>

#include "core/tiles/mission_records.h"
#include "core/tiles/tile_store.h"

namespace seamap {

// "model.onnx#hash" -> "model.onnx": another version of the same model
// continues (and replaces) the detections of the earlier one.
std::string ModelFile(const std::string& model);

// Ground distance of two nearby points in metres (equirectangular: exact
// enough at the centimetre-to-metre scale of matching).
double GroundDistanceM(const LatLon& a, const LatLon& b);

// `found` is `earlier` seen again: `earlier` is not an operator's mark, the
// class and the model file agree, and the centres are within a quarter of the
// smaller of the two objects' smaller sides, at least 10 cm.
bool SameObject(const Detection& earlier, const Detection& found);

// For each found detection, the index into `earlier` of the one it continues,
// or -1 (a new object): one to one, nearest pairs first.
std::vector<int> MatchEarlier(const std::vector<Detection>& earlier, const std::vector<Detection>& found);

// Stores one search's results (`found`: all of `source`, from the model file
// of `model`) in place of that model's earlier ones: one continuing an earlier
// detection keeps its id, creation time, note and the operator's status (a
// rejected object stays rejected, never recreated as new); earlier ones not
// found again go unless the operator confirmed or rejected them. The classes
// go first into the mission's class table (the modem record's ids), and t0
// is stored. Returns the detections as stored.
std::vector<Detection> StoreFound(TileStore& store, std::vector<Detection> found, const std::string& source,
                                  const std::string& model, const std::vector<std::string>& class_names);

}  // namespace seamap
