#include "server/event_filter.h"

#include <map>
#include <sstream>
#include <tuple>

#include <nlohmann/json.hpp>

#include "server/api_error.h"

namespace seamap::server {
namespace {

const std::set<std::string> kTypes = {"tile", "pose", "track", "detection", "progress", "trajectory"};

std::vector<std::string> SplitCommas(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ',')) parts.push_back(part);
  if (!text.empty() && text.back() == ',') parts.push_back("");
  if (text.empty()) parts.push_back("");
  return parts;
}

int ParseZoom(const std::string& text) {
  try {
    size_t used = 0;
    const int z = std::stoi(text, &used);
    if (used == text.size() && z >= 0 && z <= 30) return z;
  } catch (const std::exception&) {
  }
  throw ApiError(400, "parameter 'zoom': expected zoom levels 0..30 or ranges like 17-19, got '" + text + "'");
}

struct TileKey {
  std::string layer;
  int z = 0;
  int64_t x = 0, y = 0;
  bool operator<(const TileKey& o) const { return std::tie(layer, z, x, y) < std::tie(o.layer, o.z, o.x, o.y); }
};

std::optional<TileKey> TileOf(const Event& e) {
  if (e.type != "tile") return std::nullopt;
  try {
    const auto j = nlohmann::json::parse(e.data);
    return TileKey{j.value("layer", std::string()), j.at("z").get<int>(), j.at("x").get<int64_t>(),
                   j.at("y").get<int64_t>()};
  } catch (const std::exception&) {
    return std::nullopt;  // not a tile event this filter understands: let it through
  }
}

}  // namespace

EventFilter EventFilter::Parse(const std::optional<std::string>& types, const std::optional<std::string>& layers,
                               const std::optional<std::string>& zoom, const std::optional<std::string>& bbox) {
  EventFilter f;
  if (types) {
    f.types.emplace();
    for (const auto& t : SplitCommas(*types)) {
      if (t.empty()) continue;
      if (!kTypes.count(t))
        throw ApiError(400, "parameter 'types': unknown event type '" + t +
                                "'; expected tile, pose, track, detection or progress");
      f.types->insert(t);
    }
  }
  if (layers) {
    f.layers.emplace();
    for (const auto& l : SplitCommas(*layers)) f.layers->insert(l);
  }
  if (zoom) {
    f.zooms.emplace();
    for (const auto& part : SplitCommas(*zoom)) {
      const size_t dash = part.find('-');
      const int lo = ParseZoom(part.substr(0, dash));
      const int hi = dash == std::string::npos ? lo : ParseZoom(part.substr(dash + 1));
      if (hi < lo) throw ApiError(400, "parameter 'zoom': range '" + part + "' ends before it starts");
      for (int z = lo; z <= hi; ++z) f.zooms->insert(z);
    }
  }
  if (bbox) {
    std::vector<double> v;
    for (const auto& part : SplitCommas(*bbox)) {
      try {
        size_t used = 0;
        v.push_back(std::stod(part, &used));
        if (used != part.size()) v.clear();
      } catch (const std::exception&) {
        v.clear();
      }
      if (v.empty()) break;
    }
    if (v.size() != 4 || !(v[0] <= v[2]) || !(v[1] <= v[3]))
      throw ApiError(400,
                     "parameter 'bbox': expected west,south,east,north in degrees with west <= east and "
                     "south <= north, got '" +
                         *bbox + "'");
    f.bbox = LatLonBounds{v[0], v[1], v[2], v[3]};
  }
  return f;
}

bool EventFilter::Keep(const Event& e) const {
  if (types && !types->count(e.type)) return false;
  if (e.type != "tile" || (!layers && !zooms && !bbox)) return true;
  const auto tile = TileOf(e);
  if (!tile) return true;
  if (layers && !layers->count(tile->layer)) return false;
  if (zooms && !zooms->count(tile->z)) return false;
  if (bbox) {
    const LatLonBounds b = TileBounds(TileId{tile->z, static_cast<int>(tile->x), static_cast<int>(tile->y)});
    if (b.east < bbox->west || b.west > bbox->east || b.north < bbox->south || b.south > bbox->north) return false;
  }
  return true;
}

std::vector<Event> Coalesce(std::vector<Event> events) {
  std::map<TileKey, size_t> last_tile;
  size_t last_pose = events.size(), last_progress = events.size();
  std::vector<std::optional<TileKey>> keys(events.size());
  for (size_t i = 0; i < events.size(); ++i) {
    if (events[i].type == "pose") last_pose = i;
    if (events[i].type == "progress") last_progress = i;
    keys[i] = TileOf(events[i]);
    if (keys[i]) last_tile[*keys[i]] = i;
  }
  std::vector<Event> out;
  out.reserve(events.size());
  for (size_t i = 0; i < events.size(); ++i) {
    if (events[i].type == "pose" && i != last_pose) continue;
    if (events[i].type == "progress" && i != last_progress) continue;
    if (keys[i] && last_tile[*keys[i]] != i) continue;
    out.push_back(std::move(events[i]));
  }
  return out;
}

}  // namespace seamap::server
