#pragma once
// The server's public socket. Tiles are most of the traffic, and cpp-httplib
// spends a thread wake-up and several system calls on every request; this
// front end (libevent: one event loop per core) answers plain tile GETs itself
// and relays every other request (the REST API, live events, the console) to
// the httplib server on a loopback port, one at a time and in order. What a
// request head is comes from request_head.*, where httplib's answer ends from
// response_framer.*; this file is the event loop and connection plumbing.
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "server/tile_answer.h"

struct event_base;
struct evconnlistener;

namespace seamap::server {

// The answer to a plain tile GET: `mission_id` is empty for "/tiles/...", the
// catalogue's id for "/missions/{id}/tiles/...", `tile_path` what follows
// "/tiles/". nullopt: not this front end's to answer (the backend answers).
using TileResolver = std::function<std::optional<TileAnswer>(
    const std::string& mission_id, const std::string& tile_path, const std::optional<std::string>& if_none_match)>;

class TileFrontEnd {
 public:
  // `max_body_bytes`: the limit of a chunked request body (httplib enforces
  // it for bodies with a Content-Length).
  TileFrontEnd(TileResolver tiles, int backend_port, int loops, size_t max_body_bytes);
  ~TileFrontEnd();

  // Listens on host:port (0: any free port); throws InputError naming
  // --port/--host when it cannot. Returns the port.
  int Bind(const std::string& host, int port);
  void Start();
  void Stop();
  // Loopback connections to httplib now open (for a graceful stop).
  int proxied() const { return proxied_; }

  struct Connection;  // one client connection, in tile or pass-through mode
  struct Loop;

 private:
  TileResolver tiles_;
  int backend_port_;
  size_t max_body_bytes_;
  int listen_fd_ = -1;
  std::vector<std::unique_ptr<Loop>> loops_;
  std::vector<std::unique_ptr<std::pair<TileFrontEnd*, Loop*>>> contexts_;  // listener callback arguments
  std::vector<std::thread> threads_;
  std::atomic<int> proxied_{0};
  bool started_ = false;

  friend struct Connection;
};

}  // namespace seamap::server
