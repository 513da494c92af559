#pragma once
// The mission's detections, as every writer changes them: a recogniser's or
// stereo-locate's found objects (Publish), an operator's marks and review
// (Create, Update, Delete), and what other processes wrote to the same
// mission (Refresh). One policy for all of them:
//  - Numbering: an id is the largest the mission or this book has seen + 1
//    (never one deleted in this session); every change takes the next seq.
//  - Matching a found object to an earlier one: by id when it has one, else
//    the same source, class and model FILE NAME ("model.onnx#hash" ->
//    "model.onnx": a newer version of the same model continues the earlier
//    one's detections) within max(10 cm, a quarter of the smaller size)
//    (core/mission/detection_match.h). An operator's mark is never matched.
//  - The review stays: a match keeps its id, creation time, note and status
//    (a rejected object is never recreated as new).
//  - Replacing a model's results: that model file's unconfirmed detections the
//    batch does not hold go; confirmed and rejected ones stay.
// Every change is written to the store and flushed before it is returned or
// announced. Errors are DetectionErrors. Thread-safe.
#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/mission/detection_error.h"
#include "core/mission/detection_filter.h"
#include "core/tiles/tile_store.h"

namespace seamap {

// A batch of found objects (DetectionBook::Publish).
struct PublishOptions {
  std::vector<std::string> model_classes;  // the model's class names in order: the class table starts with them
  // Non-empty: this model file's unconfirmed detections the batch does not
  // hold go (a whole-map search replacing its earlier results).
  std::string replace_model;
};

struct PublishResult {
  std::vector<int64_t> ids;  // of the batch's detections, in batch order
  int created = 0, updated = 0, unchanged = 0, deleted = 0;
};

// One page of a query (DetectionBook::QueryPage).
struct DetectionPage {
  std::vector<Detection> detections;  // in id order
  bool more = false;                  // others pass after the last one
  int64_t last_seq = 0;
};

// Compact records for the acoustic modem (docs/MODEM_RECORD.md).
struct PackedDetections {
  std::vector<uint8_t> bytes;  // 24 bytes per record, in seq order
  size_t count = 0;
  int64_t last_seq = 0;  // the seq to ask `since` next time
};

class DetectionBook {
 public:
  // action: "created", "updated" or "deleted" (then `d` is the detection as it was).
  using Listener = std::function<void(const char* action, const Detection& d)>;

  // `store` receives every change; null for a read-only mission (writes are refused).
  explicit DetectionBook(TileStore* store, Listener listener = nullptr)
      : store_(store), listener_(std::move(listener)) {}

  void Load(const TileStore& store);
  // Load without the records that cannot be read (MissionRecords::
  // ReadableDetections), their ids in *unreadable: a pack or an export of
  // what is left instead of no answer.
  void LoadReadable(const TileStore& store, std::vector<int64_t>* unreadable);
  // Takes in what another process wrote to the mission since (stereo-locate
  // --map, seamap detect): new and changed detections and the ones it deleted,
  // announced like the book's own changes, and new classes. Every write does
  // this first, so an id is never taken twice and a PATCH never puts back
  // what another process changed.
  void Refresh(const TileStore& store);
  bool writable() const { return store_ != nullptr; }
  // Detection records the store holds but could not read, at the last Load or
  // Refresh (MissionRecords::SkippedDetections): left out, the rest is served.
  int64_t unreadable() const { return unreadable_; }

  // The detections that pass, in id order; the last seq.
  std::vector<Detection> Query(const DetectionFilter& filter, int64_t* last_seq = nullptr) const;
  // At most `limit` of them with an id above `after_id`: a long list read in
  // pages, so no answer holds them all (232,362 objects made a 188 MB answer).
  DetectionPage QueryPage(const DetectionFilter& filter, std::optional<int64_t> after_id, size_t limit) const;
  std::optional<Detection> Get(int64_t id) const;
  // An operator's mark from a GeoJSON Feature with a Point geometry.
  Detection Create(const nlohmann::json& feature);
  // A GeoJSON Feature or a properties object. A recogniser's or stereo
  // detection allows only `status` and `note` to change (others may be echoed).
  Detection Update(int64_t id, const nlohmann::json& patch);
  // Only an operator's mark can be deleted (others are rejected instead).
  void Delete(int64_t id);

  // Found objects (source "recogniser" unless "stereo"; status, note and
  // created are the book's), matched, stored, flushed and announced (an
  // unchanged one is not) by the policy above.
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
  Listener listener_;
  mutable std::mutex mutex_;
  std::map<int64_t, Detection> detections_;
  std::map<int64_t, Detection> deleted_;   // this session's deletions, seq = the deletion's
  std::map<int64_t, int64_t> stored_seq_;  // id -> seq in the store as last read or written
  std::vector<std::string> classes_;
  bool t0_stored_ = false;
  int64_t last_seq_ = 0;
  int64_t last_id_ = 0;
  std::atomic<int64_t> unreadable_{0};
};

// Publishes one search's found objects into the mission at `store` with a
// book of its own (a command's single write): replaces that model file's
// earlier unreviewed results. Returns the detections as stored, in order.
std::vector<Detection> PublishFound(TileStore& store, std::vector<Detection> found, const std::string& model,
                                    const std::vector<std::string>& class_names);

}  // namespace seamap
