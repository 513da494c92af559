#pragma once
// The one HTTP server (see server/README.md): the maps of a MissionRegistry
// (one at the root, or a folder's under /missions/{id}/), each with its
// TileJSON, tiles, REST API, live events and console, and the console's
// static files. Tiles come from TileSources, mission records from
// MissionState and DetectionRegistry, live events from EventHubs; this file
// only speaks HTTP.
#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "server/detection_registry.h"
#include "server/event_hub.h"
#include "server/http/origin_policy.h"
#include "server/mission_registry.h"
#include "server/mission_state.h"
#include "server/server_options.h"
#include "server/tile_source.h"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace seamap::server {

class HttpServer {
 public:
  // One map at the root (`seamap serve MAP`, `seamap replay`): a catalogue of one.
  HttpServer(ServerOptions options, TileSource* tiles, MissionState* mission, DetectionRegistry* detections,
             EventHub* events);
  // `seamap serve FOLDER`: a read-only catalogue of the folder's maps, GET
  // /api/missions lists them, each under /missions/{id}/. Throws InputError
  // unless `folder` is a readable folder.
  HttpServer(ServerOptions options, std::string folder);
  ~HttpServer();

  // Checks the options and binds the port; throws InputError naming the
  // option (--port, --host...) when it cannot.
  void Bind();
  int port() const { return port_; }
  // Serves until Stop(), in the calling thread or in a background thread.
  void Run();
  void Start();
  void Stop();

  // The catalogue's listing (rescanned at most once a second; empty for one map).
  std::vector<CatalogEntry> Missions() { return registry_.Missions(); }
  // The root map is a file another process may be writing: follow it.
  void FollowMap(const std::string& path, const TileStore& records) { registry_.FollowMap(path, records); }
  // Reloads the maps being built by other processes and publishes their live
  // events; call every couple of seconds.
  void Follow() { registry_.Follow(); }

 private:
  void Setup();
  void Routes();
  // What is answered before routing (true: `res` is the answer): CORS for
  // allowed origins, cross-site writes refused (403), links out of web/ (404).
  bool Screen(const httplib::Request& req, httplib::Response& res, const class WebRoot* web_root) const;
  // The tiles httplib gets from the front end (escapes, dot segments...):
  // true when `req` is one, answered.
  bool ServeTile(const httplib::Request& req, httplib::Response& res);

  ServerOptions options_;
  OriginPolicy origins_;
  MissionRegistry registry_;
  std::unique_ptr<httplib::Server> http_;      // the API, on a loopback port
  std::unique_ptr<class TileFrontEnd> front_;  // the public port: tiles itself, the rest to http_
  std::thread thread_;
  std::atomic<int> streams_{0};
  int port_ = 0;
};

}  // namespace seamap::server
