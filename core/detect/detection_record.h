#pragma once
// The recogniser's objects meet the mission: the frames that saw each one,
// and the mission's Detection record (the one conversion to keep in step
// with core/tiles/mission_records.h).
#include <vector>

#include "core/detect/recognised_object.h"
#include "core/tiles/mission_records.h"

namespace seamap {

// Sets `frames` (frames whose footprint holds the centre, nearest footprint
// centre first, up to `max_frames`) and `time_s` (the first one's time).
void AttachFrames(std::vector<RecognisedObject>& objects, const std::vector<FrameRecord>& frames,
                  size_t max_frames = 10);

// source "recogniser"; frame_id/time_s from the first frame.
Detection ToDetection(const RecognisedObject& object);

}  // namespace seamap
