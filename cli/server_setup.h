#pragma once
// Options shared by `serve` and `replay`: where to listen, the token, the
// console's folder; and the line that tells the operator where to look.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "server/server_options.h"

namespace seamap::cli {

extern const char* kServerOptionsHelp;

// The config's "server" object (from the file `source`), then --host, --port,
// --token, --web, --threads, --max-streams, --allow-origin on top; Check()ed.
server::ServerOptions ReadServerOptions(Args& args, const std::optional<nlohmann::json>& config_server,
                                        const std::string& source);

// "http://127.0.0.1:8080/" for a wildcard host, else the host itself.
std::string ServerUrl(const server::ServerOptions& options, int port);

}  // namespace seamap::cli
