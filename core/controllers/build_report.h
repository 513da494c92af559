#pragma once
// What a build says of itself when it is done: the summary line and the
// figures of --report.
#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "core/mosaic/mosaic_builder.h"
#include "core/mosaic/mosaic_plan.h"

namespace seamap {

// "frames used 10, rejected 2 (2 image); tiles written 40 (52 writes, 96 KiB); 1.20 s (10.0 frames/s)"
std::string BuildSummary(const BuildStats& stats);

// The run's figures (frames, seconds, tiles, bytes, peak RSS); `pose_report`
// (the pose source's, when not null) under "refine"; in_map: frames left out
// because their image is in the map already (--append).
nlohmann::json BuildReportJson(const BuildStats& stats, const MosaicPlan& plan, const nlohmann::json& pose_report,
                               size_t in_map);

}  // namespace seamap
