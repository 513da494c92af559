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
#include <vector>

#include <nlohmann/json.hpp>

#include "core/tiles/record_json.h"  // DetectionFeature, for the API and events
#include "core/tiles/tile_store.h"
#include "server/event_hub.h"

namespace seamap::server {

struct DetectionFilter {
  std::optional<LatLonBounds> bbox;
  std::set<std::string> classes;  // empty: all
  std::optional<double> min_score;
  std::optional<int64_t> since;    // changed after this seq
  std::set<std::string> statuses;  // empty: all ("unconfirmed", "confirmed", "rejected")
  std::set<std::string> sources;   // empty: all ("recogniser", "operator", "stereo")
};

// A recogniser's batch of found objects (DetectionRegistry::Publish).
struct PublishOptions {
  std::vector<std::string> model_classes;  // the model's class names in order: the class table starts with them
  // Non-empty: this model's unconfirmed detections the batch does not hold go
  // (a whole-map search replacing its earlier results). Reviewed ones stay.
  std::string replace_model;
};

struct PublishResult {
  std::vector<int64_t> ids;  // of the batch's detections, in batch order
  int created = 0, updated = 0, unchanged = 0, deleted = 0;
};

// Compact records for the acoustic modem (GET /api/detections.bin).
struct PackedDetections {
  std::vector<uint8_t> bytes;  // 24 bytes per record, in seq order
  size_t count = 0;
  int64_t last_seq = 0;  // the seq to ask `since` next time
};

// Parses the query parameters (bbox=w,s,e,n, class=a,b, min_score, since);
// throws ApiError(400) naming the parameter.
DetectionFilter ParseDetectionFilter(const std::optional<std::string>& bbox, const std::optional<std::string>& classes,
                                     const std::optional<std::string>& min_score,
                                     const std::optional<std::string>& since,
                                     const std::optional<std::string>& status = std::nullopt,
                                     const std::optional<std::string>& source = std::nullopt);

class DetectionRegistry {
 public:
  // `store` receives every change; null for a read-only mission (writes answer 403).
  DetectionRegistry(TileStore* store, EventHub* events) : store_(store), events_(events) {}

  void Load(const TileStore& store);
  // Takes in what another process wrote to the mission since (stereo-locate
  // --map, seamap detect): new and changed detections and the ones it deleted,
  // announced like the API's own changes, and new classes. Every write through
  // the API does this first, so an id is never taken twice and a PATCH never
  // puts back what another process changed.
  void Refresh(const TileStore& store);
  bool writable() const { return store_ != nullptr; }

  // FeatureCollection with "last_seq".
  nlohmann::json Query(const DetectionFilter& filter) const;
  std::optional<nlohmann::json> Get(int64_t id) const;
  // Throw ApiError: 400 bad body, 403 read-only or a change a recogniser's
  // detection does not allow (only `status` and `note` change; it cannot be
  // deleted), 404 unknown id.
  nlohmann::json Create(const nlohmann::json& feature);
  nlohmann::json Update(int64_t id, const nlohmann::json& patch);
  void Delete(int64_t id);

  // What a recogniser calls with its found objects (source "recogniser"
  // unless "stereo"; status, note and created are the registry's). Each is
  // matched to a published one by id, else by class, model and a centre within
  // max(10 cm, a quarter of the smaller size); a match is updated (the
  // operator's status and note kept: a rejected one stays rejected), others
  // are created. Stored, flushed once, and announced as `detection` events
  // (an unchanged one is not). Throws ApiError(403) on a read-only mission.
  PublishResult Publish(std::vector<Detection> batch, const PublishOptions& options = {});

  // Records of the detections that pass the filter and changed after
  // filter.since (deleted ones flagged so), in seq order, at most `max`.
  PackedDetections Pack(const DetectionFilter& filter, size_t max, std::optional<double> t0) const;
  // The mission's class table (class id = index).
  std::vector<std::string> Classes() const;

 private:
  void CheckWritable() const;
  void Announce(const char* action, const Detection& d);
  // Stores the detection; the class table and t0 join the metadata when new. Call with mutex_ held.
  void Store(const Detection& d);
  void Forget(std::map<int64_t, Detection>::iterator it);  // deletes, keeps a tombstone
  void RefreshLocked(const TileStore& store);

  TileStore* store_;
  EventHub* events_;
  mutable std::mutex mutex_;
  std::map<int64_t, Detection> detections_;
  std::map<int64_t, Detection> deleted_;   // this session's deletions, seq = the deletion's
  std::map<int64_t, int64_t> stored_seq_;  // id -> seq in the store as last read or written
  std::vector<std::string> classes_;
  bool t0_stored_ = false;
  int64_t last_seq_ = 0;
  int64_t last_id_ = 0;
};

}  // namespace seamap::server
