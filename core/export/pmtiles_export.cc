#include "core/export/pmtiles_export.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/tiles/record_json.h"
#include "core/util/error.h"

namespace seamap {
namespace {

PmtilesTileType TileTypeOf(const std::string& format, const std::string& source) {
  if (format == "png") return PmtilesTileType::kPng;
  if (format == "jpg" || format == "jpeg") return PmtilesTileType::kJpeg;
  if (format == "webp") return PmtilesTileType::kWebp;
  throw InputError(source, 0, "format", "tile format '" + format + "' is not png, jpg or webp");
}

// "a,b,c[,d]" -> numbers; empty when any part is not a number.
std::vector<double> Numbers(const std::string& text) {
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');) {
    try {
      size_t used = 0;
      out.push_back(std::stod(part, &used));
      if (used != part.size() || !std::isfinite(out.back())) return {};
    } catch (const std::exception&) {
      return {};
    }
  }
  return out;
}

// The dive beside its tiles, so a published archive shows what the console
// shows: the track as a GeoJSON LineString (at most kMaxTrackPoints, evenly
// kept, the last one always) and the objects as Points (rejected ones left out).
constexpr size_t kMaxTrackPoints = 20000;

nlohmann::json TrackGeoJson(const std::vector<TrackPoint>& track) {
  nlohmann::json coordinates = nlohmann::json::array();
  const size_t stride = std::max<size_t>(1, (track.size() + kMaxTrackPoints - 1) / kMaxTrackPoints);
  for (size_t i = 0; i < track.size(); i += stride)
    coordinates.push_back({track[i].position.lon, track[i].position.lat});
  if (!track.empty() && (track.size() - 1) % stride != 0)
    coordinates.push_back({track.back().position.lon, track.back().position.lat});
  return {{"type", "Feature"},
          {"geometry", {{"type", "LineString"}, {"coordinates", coordinates}}},
          {"properties", {{"points", track.size()}}}};
}

nlohmann::json ObjectsGeoJson(const std::vector<Detection>& detections) {
  nlohmann::json features = nlohmann::json::array();
  for (const Detection& d : detections) {
    if (d.status == "rejected") continue;
    nlohmann::json feature = DetectionFeature(d);
    for (const char* internal : {"seq", "frames", "box", "levels", "model"}) feature["properties"].erase(internal);
    features.push_back(std::move(feature));
  }
  return {{"type", "FeatureCollection"}, {"features", features}};
}

}  // namespace

PmtilesSummary ExportPmtiles(const TileStore& from, const std::string& source, const std::string& path,
                             const std::function<void(int64_t, int64_t)>& on_tile) {
  const auto metadata = from.Metadata();
  const std::string format = metadata.count("format") ? metadata.at("format") : "png";
  PmtilesArchiveInfo info;
  info.tile_type = TileTypeOf(format, source);

  // Clustered order: ascending Hilbert tile ids (8 + 12 bytes a tile in RAM).
  std::vector<std::pair<uint64_t, TileId>> order;
  for (const TileId& t : from.TileIds()) order.emplace_back(PmtilesTileId(t), t);
  if (order.empty()) throw InputError(source, 0, "tiles", "the map has no tiles to export");
  std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });

  // Bounds: the map's metadata, else the union of its deepest tiles.
  const int max_zoom = std::max_element(order.begin(), order.end(), [](const auto& a, const auto& b) {
                         return a.second.z < b.second.z;
                       })->second.z;
  LatLonBounds tiles{180, 90, -180, -90};
  for (const auto& [id, t] : order) {
    if (t.z != max_zoom) continue;
    const LatLonBounds b = TileBounds(t);
    tiles = {std::min(tiles.west, b.west), std::min(tiles.south, b.south), std::max(tiles.east, b.east),
             std::max(tiles.north, b.north)};
  }
  const auto bounds = metadata.count("bounds") ? Numbers(metadata.at("bounds")) : std::vector<double>{};
  info.bounds = bounds.size() == 4 ? LatLonBounds{bounds[0], bounds[1], bounds[2], bounds[3]} : tiles;
  const auto center = metadata.count("center") ? Numbers(metadata.at("center")) : std::vector<double>{};
  info.center_lon_deg = center.size() == 3 ? center[0] : (info.bounds.west + info.bounds.east) / 2;
  info.center_lat_deg = center.size() == 3 ? center[1] : (info.bounds.south + info.bounds.north) / 2;
  info.center_zoom = center.size() == 3 ? static_cast<int>(center[2]) : max_zoom;

  nlohmann::json meta = nlohmann::json::object();
  for (const auto& [k, v] : metadata) meta[k] = v;
  meta["format"] = format;
  meta["minzoom"] = std::to_string(order.front().second.z);  // ids ascend by zoom first
  meta["maxzoom"] = std::to_string(max_zoom);
  meta["seamap_track"] = TrackGeoJson(from.Records().Track());
  std::vector<int64_t> unreadable;  // inf/NaN records a recogniser once stored: left out, said
  meta["seamap_objects"] = ObjectsGeoJson(from.Records().ReadableDetections(&unreadable));
  if (!unreadable.empty())
    std::fprintf(stderr, "warning: %zu detections with non-finite or unreadable numbers not exported (first id %lld)\n",
                 unreadable.size(), static_cast<long long>(unreadable[0]));
  info.metadata_json = meta.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);

  PmtilesWriter writer(path);
  const int64_t total = static_cast<int64_t>(order.size());
  int64_t done = 0;
  for (const auto& [id, t] : order) {
    auto bytes = from.GetTile(t);
    if (!bytes || bytes->empty())
      throw InputError(source, 0, "tiles",
                       "tile " + std::to_string(t.z) + "/" + std::to_string(t.x) + "/" + std::to_string(t.y) +
                           " is listed but has no data");
    writer.Add(t, *bytes);
    if (on_tile) on_tile(++done, total);
  }
  return writer.Finish(info);
}

}  // namespace seamap
