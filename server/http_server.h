#pragma once
// The HTTP layer: routes of the REST API, tiles, live events and the console's
// static files (see server/README.md). Tiles come from a TileSource, mission
// records from MissionState and DetectionRegistry, live events from an
// EventHub; this file only speaks HTTP.
#include <atomic>
#include <memory>
#include <string>
#include <thread>

#include "server/detection_registry.h"
#include "server/event_hub.h"
#include "server/mission_state.h"
#include "server/origin_policy.h"
#include "server/server_options.h"
#include "server/tile_front_end.h"
#include "server/tile_source.h"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace seamap::server {

class HttpServer {
 public:
  HttpServer(ServerOptions options, TileSource* tiles, MissionState* mission, DetectionRegistry* detections,
             EventHub* events);
  ~HttpServer();

  // Checks the options and binds the port; throws InputError naming the
  // option (--port, --host...) when it cannot.
  void Bind();
  int port() const { return port_; }
  // Serves until Stop(), in the calling thread or in a background thread.
  void Run();
  void Start();
  void Stop();

 private:
  void Routes();
  // What is answered before routing (true: `res` is the answer): CORS for
  // allowed origins, cross-site writes refused (403), links out of web/ (404).
  bool Screen(const httplib::Request& req, httplib::Response& res, const class WebRoot* web_root) const;

  ServerOptions options_;
  OriginPolicy origins_;
  TileSource* tiles_;
  MissionState* mission_;
  DetectionRegistry* detections_;
  EventHub* events_;
  std::unique_ptr<httplib::Server> http_;      // the API, on a loopback port
  std::unique_ptr<class TileFrontEnd> front_;  // the public port: tiles itself, the rest to http_
  std::thread thread_;
  std::atomic<int> streams_{0};
  int port_ = 0;
};

}  // namespace seamap::server
