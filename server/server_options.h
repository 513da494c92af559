#pragma once
// How `serve` and `replay` run the server: the one settings type, read from
// the config file's "server" object, then the command line on top (see
// cli/server_setup), then Check()ed.
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace seamap::server {

struct ServerOptions {
  std::string host = "0.0.0.0";
  int port = 8080;        // 0: any free port
  std::string web_dir;    // the console's files; empty: no console
  std::string token;      // required for writes when not empty
  int threads = 96;       // request threads (one per open connection)
  int max_streams = 32;   // concurrent /api/events streams, on top of `threads`
  std::string photo_dir;  // where to find photos whose recorded path is gone
  // Other sites whose pages may write (and get CORS answers), e.g.
  // "http://10.0.0.5:3000"; see origin_policy.h.
  std::vector<std::string> allow_origins;

  // The defaults with the config file's "server" object applied (host, port,
  // token, threads, max_streams, allow_origins). Unknown keys, wrong types and values out of
  // range are InputErrors naming `source` (the file) and the key, e.g.
  // "config.json: field 'server.port': expected 0..65535, got 70000".
  static ServerOptions FromJson(const nlohmann::json& server, const std::string& source);

  // Throws an InputError naming the first bad option as the command line
  // spells it ("--port: expected a port number 0..65535, got 70000"); a
  // web_dir, when set, must hold the console (index.html).
  void Check() const;
};

}  // namespace seamap::server
