#include "cli/server_setup.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "core/util/error.h"

namespace seamap::cli {

const char* kServerOptionsHelp =
    "  --port N            port to listen on (default 8080; 0 picks a free one)\n"
    "  --host ADDR         address to listen on (default 0.0.0.0: every interface)\n"
    "  --token TEXT        writes (operator marks) need 'Authorization: Bearer TEXT'\n"
    "  --web DIR           the console's files (default: the web/ folder of this checkout)\n"
    "  --threads N         request threads, one per open connection (default 96)\n"
    "  --max-streams N     live event streams at once (default 32)\n"
    "  --allow-origin URL  another site whose pages may write, e.g. http://10.0.0.5:3000\n"
    "                      (repeatable; pages of other sites are refused writes, 403)\n";

server::ServerOptions ReadServerOptions(Args& args, const std::optional<nlohmann::json>& config_server,
                                        const std::string& source) {
  server::ServerOptions o =
      config_server ? server::ServerOptions::FromJson(*config_server, source) : server::ServerOptions{};
  o.host = args.GetOr("host", o.host);
  o.port = args.GetInt("port", o.port);
  o.token = args.GetOr("token", o.token);
  o.threads = args.GetInt("threads", o.threads);
  o.max_streams = args.GetInt("max-streams", o.max_streams);
  for (const std::string& origin : args.GetAll("allow-origin")) o.allow_origins.push_back(origin);
  const char* env = std::getenv("SEAMAP_WEB_DIR");
  o.web_dir = args.GetOr("web", env ? env : SEAMAP_WEB_DIR);
  o.Check();
  std::error_code ec;
  if (!std::filesystem::exists(std::filesystem::path(o.web_dir) / "vendor" / "leaflet" / "leaflet.js", ec))
    std::fprintf(stderr, "warning: %s/vendor/leaflet is missing; run scripts/setup.sh to vendor Leaflet\n",
                 o.web_dir.c_str());
  return o;
}

std::string ServerUrl(const server::ServerOptions& options, int port) {
  const std::string host = options.host == "0.0.0.0" || options.host.empty() ? "127.0.0.1" : options.host;
  return "http://" + host + ":" + std::to_string(port) + "/";
}

}  // namespace seamap::cli
