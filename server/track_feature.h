#pragma once
// The vehicle's track as GET /api/track answers it, from either source: the
// estimated track (the positions the frames were placed at, corrected where
// the trajectory was: the best the mission has), the refined one (the same
// positions, only where the trajectory was refined) or the navigation's (its
// original positions where the trajectory was corrected, the same positions
// elsewhere); or the GPS buoy's track (its fixes, given to seamap serve
// --buoy) beside the vehicle's.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/tiles/mission_records.h"

namespace seamap::server {

enum class TrackSource { kEstimated, kRefined, kNav, kBuoy };

// The `source` parameter: absent or "estimated", "refined", "nav" or "buoy"; anything else is
// ApiError 400 naming the parameter.
TrackSource ParseTrackSource(const std::optional<std::string>& text);
const char* TrackSourceName(TrackSource source);

// Where a point lies in the given source's track.
LatLon TrackPosition(const TrackPoint& point, TrackSource source);

// GeoJSON Feature: geometry a LineString of `points` (null with fewer than
// two), properties {source, corrected, from, next, times, coordinates (the
// lone point when there is no line)}. `next`: the sequence number to ask for
// next time; `corrected`: whether the mission has a corrected trajectory.
nlohmann::json TrackFeature(const std::vector<TrackPoint>& points, TrackSource source, int next, bool corrected);

}  // namespace seamap::server
