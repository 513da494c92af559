#pragma once
// JSON form of the mission records, shared by the stores (and usable by a
// server): frames and track points as objects, footprints as [[lon,lat],...].
#include <array>

#include <nlohmann/json.hpp>

#include "core/tiles/mission_records.h"

namespace seamap {

// [[lon,lat] x 4] in GeoJSON axis order.
nlohmann::json FootprintToJson(const std::array<LatLon, 4>& footprint);
std::array<LatLon, 4> FootprintFromJson(const nlohmann::json& j);

// {"id","image","image_path","time_s" (null when unknown),"lat","lon","altitude_m",
//  "depth_m","heading_deg","pitch_deg","roll_deg","footprint","status"}, plus
// "nav_lat","nav_lon","nav_altitude_m","nav_depth_m","nav_heading_deg","nav_pitch_deg",
// "nav_roll_deg" when the frame was placed with a corrected pose (absent otherwise).
nlohmann::json FrameToJson(const FrameRecord& f);
FrameRecord FrameFromJson(const nlohmann::json& j);  // throws nlohmann::json::exception

// {"seq","time_s","lat","lon","altitude_m","depth_m","heading_deg"}, plus
// "nav_lat","nav_lon","nav_heading_deg" when the point is a corrected position.
nlohmann::json TrackPointToJson(const TrackPoint& p);
TrackPoint TrackPointFromJson(const nlohmann::json& j);

// {"id","class","score","lat","lon","note","source","model","level","levels","box","position_m",
//  "size_m","frames","frame_id","time_s","status","truncated","alt_class","created","updated","seq"};
// box is a [[lon,lat],...] ring, position_m [east, north], size_m [ew, ns] (null when unknown).
// Reading normalises an older record (NormaliseDetection).
nlohmann::json BoxToJson(const std::vector<LatLon>& ring);
std::vector<LatLon> BoxFromJson(const nlohmann::json& j);
nlohmann::json DetectionToJson(const Detection& d);
// A GeoJSON Feature: Point at the position, every stored field but lat/lon as properties.
nlohmann::json DetectionFeature(const Detection& d);
Detection DetectionFromJson(const nlohmann::json& j);

}  // namespace seamap
