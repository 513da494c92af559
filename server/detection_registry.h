#pragma once
// The mission's detections behind the REST API: queries with filters, and
// operator marks created, changed and deleted through the API. Every change
// is written through to the mission store (and flushed) before it is
// answered or announced. Thread-safe.
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "core/tiles/tile_store.h"
#include "server/event_hub.h"

namespace seamap::server {

struct DetectionFilter {
  std::optional<LatLonBounds> bbox;
  std::set<std::string> classes;  // empty: all
  std::optional<double> min_score;
  std::optional<int64_t> since;  // changed after this seq
};

// Parses the query parameters (bbox=w,s,e,n, class=a,b, min_score, since);
// throws ApiError(400) naming the parameter.
DetectionFilter ParseDetectionFilter(const std::optional<std::string>& bbox, const std::optional<std::string>& classes,
                                     const std::optional<std::string>& min_score,
                                     const std::optional<std::string>& since);

// GeoJSON Feature of a detection (Point geometry, properties, id).
nlohmann::json DetectionFeature(const Detection& d);

class DetectionRegistry {
 public:
  // `store` receives every change; null for a read-only mission (writes answer 403).
  DetectionRegistry(TileStore* store, EventHub* events) : store_(store), events_(events) {}

  void Load(const TileStore& store);
  bool writable() const { return store_ != nullptr; }

  // FeatureCollection with "last_seq".
  nlohmann::json Query(const DetectionFilter& filter) const;
  std::optional<nlohmann::json> Get(int64_t id) const;
  // Throw ApiError: 400 bad body, 403 not an operator mark / read-only, 404 unknown id.
  nlohmann::json Create(const nlohmann::json& feature);
  nlohmann::json Update(int64_t id, const nlohmann::json& patch);
  void Delete(int64_t id);

 private:
  void CheckWritable() const;
  // The operator mark with this id (404 unknown, 403 a recogniser's); call with mutex_ held.
  std::map<int64_t, Detection>::iterator OperatorMark(int64_t id, const char* verb);
  void Announce(const char* action, const Detection& d);

  TileStore* store_;
  EventHub* events_;
  mutable std::mutex mutex_;
  std::map<int64_t, Detection> detections_;
  int64_t last_seq_ = 0;
  int64_t last_id_ = 0;
};

}  // namespace seamap::server
