#pragma once
// A new search of the map meets the detections already in the mission: which
// earlier detection each fresh one continues (spec sect. 8.7), the rule of the
// detection book (core/mission/detection_book.h) for every writer.
#include <string>
#include <vector>

#include "core/tiles/mission_records.h"

namespace seamap {

// "model.onnx#hash" -> "model.onnx": another version of the same model
// continues (and replaces) the detections of the earlier one.
std::string ModelFile(const std::string& model);

// Ground distance of two nearby points in metres (equirectangular: exact
// enough at the centimetre-to-metre scale of matching).
double GroundDistanceM(const LatLon& a, const LatLon& b);

// `found` is `earlier` seen again: `earlier` is not an operator's mark, the
// source, the class and the model file agree, and the centres are within a quarter of the
// smaller of the two objects' smaller sides, at least 10 cm.
bool SameObject(const Detection& earlier, const Detection& found);

// For each found detection, the index into `earlier` of the one it continues,
// or -1 (a new object): one to one, nearest pairs first.
std::vector<int> MatchEarlier(const std::vector<Detection>& earlier, const std::vector<Detection>& found);

}  // namespace seamap
