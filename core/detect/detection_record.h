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

// Stores the recogniser's objects in the mission, replacing the earlier
// detections of the same model file (`model`: "name.onnx#hash"): one matching
// a new object (same class, centres within max(10 cm, a quarter of the
// smaller size)) keeps its id, creation time, note and the operator's status
// (a rejected object stays rejected, never recreated as new); unmatched ones
// go unless the operator confirmed or rejected them. Returns the detections
// as stored.
// The model's class names go first into the mission's class table (the
// modem record's class ids), and t0 is stored.
std::vector<Detection> StoreRecognised(TileStore& store, const std::vector<RecognisedObject>& objects,
                                       const std::string& model, const std::vector<std::string>& class_names);

// A GeoJSON FeatureCollection: a Point at each centre, the box and the rest as properties.
nlohmann::json RecognisedFeatureCollection(const std::vector<RecognisedObject>& objects);

}  // namespace seamap
