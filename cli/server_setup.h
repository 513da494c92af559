#pragma once
// Options shared by `serve` and `replay`: where to listen, the token, the
// console's folder; and the line that tells the operator where to look.
#include <string>

#include "cli/args.h"
#include "core/mosaic/build_config.h"
#include "server/http_server.h"

namespace seamap::cli {

extern const char* kServerOptionsHelp;

// --host, --port, --token, --web, --threads, --max-streams, --images over the config's "server".
server::ServerOptions ReadServerOptions(Args& args, const ServerSettings& settings);

// "http://127.0.0.1:8080/" for a wildcard host, else the host itself.
std::string ServerUrl(const server::ServerOptions& options, int port);

}  // namespace seamap::cli
