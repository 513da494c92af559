#pragma once
// What one live event stream wants (GET /api/events?types=&layers=&zoom=&bbox=):
// a console on a weak link asks only for the layers, zoom levels and area in
// view. Coalesce() drops what a later event of the same batch supersedes
// (a tile rewritten twice, an older pose or progress), keeping event order.
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/geo/web_mercator.h"
#include "server/event_hub.h"

namespace seamap::server {

struct EventFilter {
  std::optional<std::set<std::string>> types;   // null: every type
  std::optional<std::set<std::string>> layers;  // tile events; "" is the main map
  std::optional<std::set<int>> zooms;           // tile events
  std::optional<LatLonBounds> bbox;             // tile events whose tile meets it

  // Parses the query parameters; throws ApiError(400) naming the parameter.
  // types: a,b (of tile, pose, track, detection, progress); layers: a,b (empty
  // item = the main map); zoom: a list of levels or ranges ("17-19,21");
  // bbox: west,south,east,north in degrees.
  static EventFilter Parse(const std::optional<std::string>& types, const std::optional<std::string>& layers,
                           const std::optional<std::string>& zoom, const std::optional<std::string>& bbox);

  bool Keep(const Event& event) const;
};

// Keeps the last of each tile (layer, z, x, y), the last pose and the last
// progress of a batch; every other event stays. Order is kept.
std::vector<Event> Coalesce(std::vector<Event> events);

}  // namespace seamap::server
