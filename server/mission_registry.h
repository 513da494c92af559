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
#include <cstdint>
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

// What a map's file was when it was opened: another file moved over it
// (another inode), or a finished map rewritten in place, is opened again.
struct MapFileStamp {
  uint64_t device = 0, inode = 0;
  int64_t size = 0, modified_ns = 0;
  bool operator==(const MapFileStamp& o) const {
    return device == o.device && inode == o.inode && size == o.size && modified_ns == o.modified_ns;
  }
};
// The map at `path` (a folder map: its metadata.json) now; nullopt when it is gone.
std::optional<MapFileStamp> StampOf(const std::string& path);

class MissionRegistry {
 public:
  // Past ~90 open missions the process ran out of file handles ("unable to open database file").
  static constexpr size_t kMaxOpenMissions = 32;

  // One map at the root; `token_required`: writes need the server's token.
  MissionRegistry(TileSource* tiles, MissionState* mission, DetectionRegistry* detections, EventHub* events,
                  bool token_required);
  // The maps of `folder`; throws InputError unless it is a readable folder.
  // At most `max_open` missions are open at once (each holds about a dozen
  // file handles): opening another closes the least recently used.
  MissionRegistry(std::string folder, bool token_required, size_t max_open = kMaxOpenMissions);
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
  // until its file changes or it is the least recently used of too many
  // (open event streams keep it alive until they end).
  struct OpenMission;
  // A catalogue mission's tile source, and what its file was when opened.
  struct OpenSource {
    std::shared_ptr<TileSource> source;
    MapFileStamp stamp;
    uint64_t used = 0;  // use_clock_ at its last request
  };

  // The listing's entry for id and its tile source (made when new, outside
  // mutex_); throws ApiError 404 like Tiles().
  std::pair<CatalogEntry, std::shared_ptr<TileSource>> Entry(const std::string& id);
  // The entry for id under mutex_ (held); throws like Tiles().
  const CatalogEntry& EntryLocked(const std::string& id);
  // Closes the maps whose file changed or left the listing (called after a rescan).
  void CloseChanged();
  // Closes the map at `path` (mutex_ held): its source and records go, its streams end.
  void CloseLocked(const std::string& path);
  // Closes the least recently used maps until at most max_open_ are open (mutex_ held).
  void EvictLocked();

  bool token_required_;
  size_t max_open_ = kMaxOpenMissions;
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
  uint64_t use_clock_ = 0;                                    // counts requests, for the LRU
  std::map<std::string, OpenSource> sources_;                 // by map path
  std::map<std::string, std::shared_ptr<OpenMission>> open_;  // by map path; each has a source in sources_
};

}  // namespace seamap::server
