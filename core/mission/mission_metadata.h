#pragma once
// What SeaMap keeps about a mission in its map's metadata (the `seamap_*`
// keys of the MBTiles metadata table / the folder's metadata.json), typed.
// Every reader goes through ReadMissionMetadata and every writer through
// WriteMissionMetadata, so a key's name, text format and default live here
// once. The plain TileJSON keys (name, format, minzoom, bounds...) are not
// the mission's and stay strings.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geo/lat_lon.h"

namespace seamap {

class TileStore;

struct MissionMetadata {
  // seamap_state: "building", "complete", "stopped" (a replay its operator stopped).
  std::optional<std::string> state;
  // seamap_layers "raw,enhanced": the first is the map itself, the others OpenLayer's.
  std::optional<std::vector<std::string>> layers;
  std::optional<LatLon> origin;                     // seamap_origin "lat,lon": the local frame's origin (position_m)
  std::optional<nlohmann::json> trajectory;         // seamap_trajectory: how the poses were estimated
  std::optional<double> t0;                         // seamap_t0: the first frame's time, s (modem record times)
  std::optional<std::vector<std::string>> classes;  // seamap_classes: the class table (class id = index)
  std::optional<int> tile_size_px;                  // seamap_tile_size
  std::optional<double> gsd_m;                      // seamap_gsd_m: ground size of a base-zoom pixel
  std::optional<int> channels;                      // seamap_channels: 1 gray, 3 colour
  std::optional<int> frames_used, frames_rejected;  // seamap_frames_used / _rejected
  // seamap_relief: the relief layer made from the height model (core/mission/relief_layer.h):
  // {"layer", "low_m", "high_m" (the colour ramp's ends), "datum", "minzoom", "maxzoom"}.
  std::optional<nlohmann::json> relief;

  // Keys present whose text could not be read (their field stays unset).
  std::set<std::string> unreadable;

  // The layer list, {"raw"} when none is recorded (a map before layers).
  std::vector<std::string> LayersOrRaw() const;
  // The layers besides the map itself (layers[1..]).
  std::vector<std::string> ExtraLayers() const;
  // The recorded state, "" when none.
  std::string StateOrEmpty() const { return state.value_or(""); }
};

// The metadata keys, for the few places that must name one (errors, TileJSON).
constexpr const char* kStateKey = "seamap_state";
constexpr const char* kLayersKey = "seamap_layers";
constexpr const char* kOriginKey = "seamap_origin";
constexpr const char* kTrajectoryKey = "seamap_trajectory";
constexpr const char* kT0Key = "seamap_t0";
constexpr const char* kClassTableKey = "seamap_classes";
constexpr const char* kTileSizeKey = "seamap_tile_size";
constexpr const char* kGsdKey = "seamap_gsd_m";
constexpr const char* kChannelsKey = "seamap_channels";
constexpr const char* kFramesUsedKey = "seamap_frames_used";
constexpr const char* kFramesRejectedKey = "seamap_frames_rejected";
constexpr const char* kReliefKey = "seamap_relief";

// Reads every seamap_* key of a store's metadata; missing ones stay unset.
MissionMetadata ReadMissionMetadata(const std::map<std::string, std::string>& metadata);
MissionMetadata ReadMissionMetadata(const TileStore& store);

// Writes the fields that are set (others are left as stored), in the open
// transaction (no flush). Numbers are written as the builder always has: so
// that maps stay byte-identical.
void WriteMissionMetadata(TileStore* store, const MissionMetadata& metadata);

// The mission's origin, required: throws InputError naming the map at `path`
// and seamap_origin when it is absent or unreadable.
LatLon RequireMissionOrigin(const MissionMetadata& metadata, const std::string& path);

// The layer list as seamap_layers writes it ("raw,enhanced").
std::string LayerListText(const std::vector<std::string>& layers);

}  // namespace seamap
