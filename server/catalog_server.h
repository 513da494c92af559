#pragma once
// `seamap serve FOLDER`: a catalogue of the maps in a folder over HTTP.
// GET /api/missions lists them (core/mission/map_catalog); each available one
// is served read-only under /missions/{id}/: the operator console (/), its
// TileJSON and tiles/[{layer}/]{z}/{x}/{y}.{ext} through its own TileSource,
// and the mission's API and live events (api/..., server/mission_api.h).
// Maps added to the folder appear on the next listing; unavailable ones are
// listed with the reason. A mission another process is still building is
// followed (Follow) and its browsers get live events.
#include <atomic>
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/mission/map_catalog.h"
#include "core/tiles/tile_store.h"
#include "server/detection_registry.h"
#include "server/event_hub.h"
#include "server/mission_api.h"
#include "server/mission_state.h"
#include "server/server_options.h"
#include "server/tile_answer.h"
#include "server/tile_source.h"

namespace httplib {
class Server;
}

namespace seamap::server {

class CatalogServer {
 public:
  CatalogServer(ServerOptions options, std::string folder);
  ~CatalogServer();

  // Throws InputError naming --port/--host when the port cannot be bound.
  void Bind();
  int port() const { return port_; }
  void Start();
  void Stop();

  // The current listing (rescanned at most once a second).
  std::vector<CatalogEntry> Missions();

  // Reloads the opened missions that are being built (or just stopped
  // being) and publishes their live events; call every couple of seconds.
  void Follow();

 private:
  // One mission's records and live events, opened at its first API request
  // and kept while serving (open event streams read its hub).
  struct OpenMission {
    std::unique_ptr<TileStore> records;
    MissionState mission;
    EventHub events;
    std::unique_ptr<DetectionRegistry> detections;
    std::string state;  // as last published
  };

  void Routes();
  // A tile of a mission for the front end; nullopt for an unknown or
  // unavailable id (httplib then answers the JSON 404).
  std::optional<TileAnswer> AnswerMissionTile(const std::string& id, const std::string& path,
                                              const std::optional<std::string>& if_none_match);
  // The mission's API services; throws ApiError 404 like Mission().
  MissionServices Services(const std::string& id);
  // Rescans when the listing is over a second old (mutex_ not held); while
  // one thread rescans, the others go on with the listing as it is.
  void Refresh();
  // The mission's tiles; throws ApiError 404 for an unknown or unavailable id.
  std::pair<CatalogEntry, std::shared_ptr<TileSource>> Mission(const std::string& id);
  // The listing's entry for id, its tile source made if new; throws like Mission(). Call with mutex_ held.
  const CatalogEntry& MissionLocked(const std::string& id);

  ServerOptions options_;
  MapCatalog catalog_;
  std::unique_ptr<httplib::Server> http_;      // on a loopback port
  std::unique_ptr<class TileFrontEnd> front_;  // the public port: tiles itself, the rest to http_
  std::thread thread_;
  int port_ = 0;

  std::mutex mutex_;  // guards what follows
  std::vector<CatalogEntry> listing_;
  std::chrono::steady_clock::time_point scanned_{};
  bool scanning_ = false;                                       // catalog_ is used by the scanning thread alone
  std::map<std::string, std::shared_ptr<TileSource>> sources_;  // by map path
  std::map<std::string, std::unique_ptr<OpenMission>> open_;    // by map path
  std::atomic<int> streams_{0};
};

}  // namespace seamap::server
