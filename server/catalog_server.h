#pragma once
// `seamap serve FOLDER`: a catalogue of the maps in a folder over HTTP.
// GET /api/missions lists them (core/tiles/map_catalog); each available one
// is served read-only under /missions/{id}/: tiles.json (TileJSON) and
// tiles/[{layer}/]{z}/{x}/{y}.{ext}, each through its own TileSource; the
// console's files are served from web_dir. Maps added to the folder appear
// on the next listing; unavailable ones are listed with the reason.
#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/tiles/map_catalog.h"
#include "server/server_options.h"
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

 private:
  void Routes();
  void RefreshLocked();  // rescans when the listing is over a second old; mutex_ held
  // The mission's tiles; throws ApiError 404 for an unknown or unavailable id.
  std::pair<CatalogEntry, std::shared_ptr<TileSource>> Mission(const std::string& id);

  ServerOptions options_;
  MapCatalog catalog_;
  std::unique_ptr<httplib::Server> http_;
  std::thread thread_;
  int port_ = 0;

  std::mutex mutex_;  // guards what follows
  std::vector<CatalogEntry> listing_;
  std::chrono::steady_clock::time_point scanned_{};
  std::map<std::string, std::shared_ptr<TileSource>> sources_;  // by map path
};

}  // namespace seamap::server
