#pragma once
// The maps one server serves, by id (Martin's catalogue of sources): one map
// at the root (`seamap serve MAP`, `seamap replay`: id "", its records the
// caller's), or the maps of a folder (`seamap serve FOLDER`: each under
// /missions/{id}/, listed by core/tiles/map_catalog, opened read-only at its
// first API request). A single map is a catalogue of one: the server asks
// both the same questions. Maps another process is writing are followed
// (core/mission/map_follower) and what changes becomes live events.
// Knows nothing of HTTP beyond ApiError. Thread-safe.
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/mission/map_catalog.h"
#include "core/tiles/tile_store.h"
#include "server/detection_registry.h"
#include "server/event_hub.h"
#include "server/mission_api.h"
#include "server/mission_state.h"
#include "server/tile_answer.h"
#include "server/tile_source.h"

namespace seamap::server {

// A mission's tiles as a request sees them.
struct MissionTiles {
  std::shared_ptr<TileSource> source;
  bool building = false;  // still growing: browsers must revalidate
  std::string name;       // the TileJSON's name where the map records none
};

class MissionRegistry {
 public:
  // One map at the root; `token_required`: writes need the server's token.
  MissionRegistry(TileSource* tiles, MissionState* mission, DetectionRegistry* detections, EventHub* events,
                  bool token_required);
  // The maps of `folder`; throws InputError unless it is a readable folder.
  MissionRegistry(std::string folder, bool token_required);
  ~MissionRegistry();

  // Missions under /missions/{id}/ (a folder) rather than one at the root.
  bool catalogue() const { return catalog_ != nullptr; }
  // The folder's listing, rescanned when over a second old (empty for one map).
  std::vector<CatalogEntry> Missions();
  // Rescans now unless the listing is fresh or another thread is rescanning.
  void Refresh();

  // Throw ApiError 404 for an unknown or unavailable id ("": the root map).
  MissionTiles Tiles(const std::string& id);
  MissionServices Services(const std::string& id);
  // A tile for the front end: nullopt where the id names no map (the backend answers why).
  std::optional<TileAnswer> AnswerMissionTile(const std::string& id, const std::string& path,
                                              const std::optional<std::string>& if_none_match);

  // Follows the root map's file at `path`, which another process may be
  // writing: its state is published now, changes at each Follow().
  void FollowMap(const std::string& path, const TileStore& records);
  // Reloads the followed maps that are being built (or just stopped being)
  // and publishes their live events, and takes in the detections another
  // process stored; call every couple of seconds. No lock is held while the
  // map files are read.
  void Follow();
  // Ends every mission's event streams (the server is stopping).
  void CloseEvents();

 private:
  struct Followed;
  // A catalogue mission's records, opened at its first API request and kept
  // while serving (open event streams read its hub).
  struct OpenMission;

  // The listing's entry for id and its tile source (made when new, outside
  // mutex_); throws ApiError 404 like Tiles().
  std::pair<CatalogEntry, std::shared_ptr<TileSource>> Entry(const std::string& id);
  // The entry for id under mutex_ (held); throws like Tiles().
  const CatalogEntry& EntryLocked(const std::string& id);

  bool token_required_;
  // One map: the caller's records; `root_` follows them when FollowMap() was called.
  TileSource* root_tiles_ = nullptr;
  MissionState* root_mission_ = nullptr;
  DetectionRegistry* root_detections_ = nullptr;
  EventHub* root_events_ = nullptr;
  std::unique_ptr<Followed> root_;

  std::unique_ptr<MapCatalog> catalog_;  // a folder; used by the scanning thread alone
  // Held while a mission's tile source or records are opened (SQLite, outside
  // mutex_): the requests that arrive together for a mission not yet open wait
  // for one opening instead of each opening its own (64 at once took the
  // catalogue's p99 from 5 to 50 ms).
  std::mutex opening_;
  std::mutex mutex_;  // guards what follows
  std::vector<CatalogEntry> listing_;
  std::chrono::steady_clock::time_point scanned_{};
  bool scanning_ = false;
  std::map<std::string, std::shared_ptr<TileSource>> sources_;  // by map path
  std::map<std::string, std::unique_ptr<OpenMission>> open_;    // by map path; never closed while serving
};

}  // namespace seamap::server
