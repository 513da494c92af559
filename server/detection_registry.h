#pragma once
// The mission's detection book (core/mission/detection_book.h) behind the
// REST API: its answers as GeoJSON, its changes as `detection` events, and
// its DetectionErrors as ApiErrors (kNotFound 404, kInvalid 400, kRefused 403)
// with the same messages. Thread-safe.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mission/detection_book.h"
#include "core/tiles/record_json.h"  // DetectionFeature, for the API and events
#include "core/tiles/tile_store.h"
#include "server/event_hub.h"

namespace seamap::server {

using seamap::DetectionFilter;
using seamap::PackedDetections;
using seamap::PublishOptions;
using seamap::PublishResult;

// The HTTP status of a book's refusal.
int HttpStatus(DetectionError::Kind kind);

// The query parameters (bbox=w,s,e,n, class=a,b, min_score, since, status,
// source); throws ApiError(400) "parameter 'NAME': ...".
DetectionFilter ParseDetectionFilter(const std::optional<std::string>& bbox, const std::optional<std::string>& classes,
                                     const std::optional<std::string>& min_score,
                                     const std::optional<std::string>& since,
                                     const std::optional<std::string>& status = std::nullopt,
                                     const std::optional<std::string>& source = std::nullopt);

class DetectionRegistry {
 public:
  // `store` receives every change; null for a read-only mission (writes answer 403).
  DetectionRegistry(TileStore* store, EventHub* events);

  void Load(const TileStore& store) { book_.Load(store); }
  void Refresh(const TileStore& store) { book_.Refresh(store); }
  bool writable() const { return book_.writable(); }

  // FeatureCollection with "last_seq".
  nlohmann::json Query(const DetectionFilter& filter) const;
  // One page of it: at most `limit` features with an id above `after_id`;
  // *more: others follow.
  nlohmann::json QueryPage(const DetectionFilter& filter, std::optional<int64_t> after_id, size_t limit,
                           bool* more) const;
  // Records the mission holds but could not read (skipped, see DetectionBook::unreadable).
  int64_t Unreadable() const { return book_.unreadable(); }
  std::optional<nlohmann::json> Get(int64_t id) const;
  // The book's, answered as a Feature; throw ApiError.
  nlohmann::json Create(const nlohmann::json& feature);
  nlohmann::json Update(int64_t id, const nlohmann::json& patch);
  void Delete(int64_t id);
  PublishResult Publish(std::vector<Detection> batch, const PublishOptions& options = {});

  PackedDetections Pack(const DetectionFilter& filter, size_t max, std::optional<double> t0) const {
    return book_.Pack(filter, max, t0);
  }
  std::vector<std::string> Classes() const { return book_.Classes(); }

 private:
  DetectionBook book_;
};

}  // namespace seamap::server
