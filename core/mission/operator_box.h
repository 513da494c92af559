#pragma once
// The box an operator draws around an object the recogniser missed (issue
// 32): stored like a recogniser's, as `box` (a ring NW, SW, SE, NE, NW of
// [lon, lat]) and `size_m` ([east-west, north-south] metres), so the
// console draws it and `seamap training-data` labels it.
#include <nlohmann/json.hpp>

#include "core/tiles/mission_records.h"

namespace seamap {

constexpr double kMaxOperatorBox_m = 50;  // a side; larger is a slip of the mouse

// Sets d->box and d->size_m from the properties `box` (a closed ring of 5
// [lon, lat] points whose bounds are the box; any axis-aligned rectangle, or
// a rotated one by its bounds) and/or `size_m` ([w, h] metres around
// d->position). With both, size_m must agree with the box (1 cm). A null
// value removes the box (a point mark again). d->position must lie inside the
// box. Throws DetectionError::Invalid naming properties.box or properties.size_m.
// Either pointer may be null (not given).
void ApplyOperatorBox(const nlohmann::json* box, const nlohmann::json* size_m, Detection* d);

}  // namespace seamap
