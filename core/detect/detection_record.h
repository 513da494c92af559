#pragma once
// The recogniser's objects meet the mission: the frames that saw each one,
// and the mission's Detection record (the one conversion to keep in step
// with core/tiles/mission_records.h).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/detect/recognised_object.h"
#include "core/tiles/mission_records.h"
#include "core/tiles/tile_store.h"

namespace seamap {

// Sets `frames` (frames whose footprint holds the centre, nearest footprint
// centre first, up to `max_frames`) and `time_s` (the first one's time).
void AttachFrames(std::vector<RecognisedObject>& objects, const std::vector<FrameRecord>& frames,
                  size_t max_frames = 10);

// source "recogniser"; frame_id/time_s from the first frame.
Detection ToDetection(const RecognisedObject& object);

// The recogniser's objects stored in the mission (PublishFound, source
// "recogniser", `model`: "name.onnx#hash"): ids, notes and the operator's
// review carried over from the same model file's earlier search.
std::vector<Detection> StoreRecognised(TileStore& store, const std::vector<RecognisedObject>& objects,
                                       const std::string& model, const std::vector<std::string>& class_names);

// A GeoJSON FeatureCollection: a Point at each centre, the box and the rest as properties.
nlohmann::json RecognisedFeatureCollection(const std::vector<RecognisedObject>& objects);

}  // namespace seamap
