#include "server/http_server.h"

#include <httplib.h>

#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>

#include "core/tiles/folder_store.h"
#include "core/util/error.h"
#include "server/api_error.h"
#include "server/http/http_util.h"
#include "server/http/tile_front_end.h"
#include "server/http/web_root.h"
#include "server/mission_api.h"
#include "server/tile_answer.h"

namespace seamap::server {
namespace {

// A catalogue mission's URLs start with this; its id is the first capture.
constexpr char kMissionPrefix[] = R"(/missions/([a-z0-9_-]+))";

nlohmann::json EntryJson(const CatalogEntry& e) {
  nlohmann::json j = {{"id", e.id},
                      {"name", e.name},
                      {"state", e.available ? e.state : "unavailable"},
                      {"available", e.available},
                      {"file", std::filesystem::path(e.path).filename().string()},
                      {"modified_unix_s", e.modified_unix_s}};
  if (!e.available) {
    j["reason"] = e.reason;
    return j;
  }
  j["bounds"] = e.bounds ? nlohmann::json{e.bounds->west, e.bounds->south, e.bounds->east, e.bounds->north}
                         : nlohmann::json(nullptr);
  j["minzoom"] = e.min_zoom;
  j["maxzoom"] = e.max_zoom;
  j["frames"] = e.frames;
  j["time_s"] = {{"first", e.first_time_s ? nlohmann::json(*e.first_time_s) : nlohmann::json(nullptr)},
                 {"last", e.last_time_s ? nlohmann::json(*e.last_time_s) : nlohmann::json(nullptr)}};
  j["layers"] = e.layers;
  j["tilejson"] = "/missions/" + e.id + "/tiles.json";
  return j;
}

// Where a mission's URLs start: "" for the root map.
std::string MissionPath(const std::string& id) {
  return id.empty() ? "" : "/missions/" + id;
}

// Headers are added, not replaced, by httplib: one set before routing stays the only one.
void SetHeaderOnce(httplib::Response& res, const std::string& name, const std::string& value) {
  if (!res.has_header(name.c_str())) res.set_header(name, value);
}

}  // namespace

HttpServer::HttpServer(ServerOptions options, TileSource* tiles, MissionState* mission, DetectionRegistry* detections,
                       EventHub* events)
    : options_(std::move(options)),
      origins_(options_.allow_origins),
      registry_(tiles, mission, detections, events, !options_.token.empty()),
      http_(std::make_unique<BacklogServer>()) {
  Setup();
}

HttpServer::HttpServer(ServerOptions options, std::string folder)
    : options_(std::move(options)),
      origins_(options_.allow_origins),
      registry_(std::move(folder), !options_.token.empty()),
      http_(std::make_unique<BacklogServer>()) {
  Setup();
}

HttpServer::~HttpServer() {
  Stop();
}

void HttpServer::Setup() {
  // Each open event stream holds a thread: the pool has room for them beside the requests.
  const size_t threads = static_cast<size_t>(std::max(2, options_.threads) + std::max(1, options_.max_streams));
  http_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  http_->set_payload_max_length(kMaxRequestBody);
  http_->set_keep_alive_max_count(10000);  // httplib's default (5) reconnects every 5 requests
  http_->set_keep_alive_timeout(5);
  http_->set_tcp_nodelay(true);
  // httplib's default options add SO_REUSEPORT, with which a second server binds
  // the same port and silently takes half the connections. SO_REUSEADDR alone
  // still allows a quick restart, and a port in use fails Bind() as it should.
  http_->set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  Routes();
}

bool HttpServer::ServeTile(const httplib::Request& req, httplib::Response& res) {
  if (req.method != "GET" && req.method != "HEAD") return false;
  const std::string& path = req.path;
  if (path.size() > 5 && path.compare(path.size() - 5, 5, ".json") == 0) return false;  // TileJSON
  std::string id, tile_path;
  if (!registry_.catalogue()) {
    if (path.rfind("/tiles/", 0) != 0) return false;
    tile_path = path.substr(7);
  } else {
    static const std::regex kMissionTile(R"(/missions/([a-z0-9_-]+)/tiles/(.+))");
    std::smatch m;
    if (!std::regex_match(path, m, kMissionTile)) return false;
    id = m[1].str();
    tile_path = m[2].str();
  }
  try {
    MissionTiles tiles = registry_.Tiles(id);
    std::optional<std::string> if_none_match;
    if (req.has_header("If-None-Match")) if_none_match = req.get_header_value("If-None-Match");
    TileAnswer a = AnswerTile(*tiles.source, tiles.building, tile_path, if_none_match);
    res.status = a.status;
    for (const auto& [name, value] : a.headers) SetHeaderOnce(res, name, value);
    if (a.body) res.set_content(a.body->data(), a.body->size(), a.content_type.c_str());
  } catch (const ApiError& e) {
    SendError(res, e.status(), e.what());
  } catch (const std::exception& e) {
    SendError(res, 500, e.what());
  }
  return true;
}

void HttpServer::Routes() {
  httplib::Server& s = *http_;
  const bool catalogue = registry_.catalogue();
  // A catalogue's routes are under the mission's prefix, whose id is capture 1.
  const std::string P = catalogue ? kMissionPrefix : "";
  const int k = catalogue ? 1 : 0;
  auto mission_id = [k](const httplib::Request& req) { return k ? std::string(req.matches[1]) : std::string(); };

  if (catalogue)
    s.Get("/api/missions", Guard([this](const httplib::Request&, httplib::Response& res) {
            nlohmann::json list = nlohmann::json::array();
            for (const auto& e : registry_.Missions()) list.push_back(EntryJson(e));
            res.set_header("Cache-Control", "no-cache");
            SendJson(res, list);
          }));

  s.Get(P + R"(/tiles(/[a-z0-9_]{1,32})?\.json)",
        Guard([this, k, mission_id](const httplib::Request& req, httplib::Response& res) {
          const std::string id = mission_id(req);
          const MissionTiles tiles = registry_.Tiles(id);
          const std::string layer = req.matches[k + 1].length() > 0 ? std::string(req.matches[k + 1]).substr(1) : "";
          if (!layer.empty() && !tiles.source->IsLayer(layer)) throw ApiError(404, "no layer '" + layer + "'");
          const std::string ext = tiles.source->Format();
          std::map<std::string, std::string> metadata = tiles.source->Metadata(layer);
          for (auto it = metadata.begin(); it != metadata.end();)  // other layers' keys stay in their own TileJSON
            it = it->first.rfind("layer.", 0) == 0 ? metadata.erase(it) : std::next(it);
          nlohmann::json j = MetadataToTileJson(metadata, ext);
          const std::string host = req.has_header("Host") ? req.get_header_value("Host") : "127.0.0.1";
          j["tiles"] = {"http://" + host + MissionPath(id) + "/tiles/" + (layer.empty() ? "" : layer + "/") +
                        "{z}/{x}/{y}." + ext};
          if (!j.contains("name")) j["name"] = tiles.name;
          if (!j.contains("attribution")) j["attribution"] = "";
          j["seamap_layers"] = tiles.source->Layers();
          j["seamap_formats"] = tiles.source->Formats();  // the stored format first, then what it is also served as
          SetHeaderOnce(res, "Access-Control-Allow-Origin", "*");
          res.set_header("Cache-Control", "no-cache");
          SendJson(res, j);
        }));

  std::optional<WebRoot> web_root;
  if (!options_.web_dir.empty()) web_root.emplace(options_.web_dir);
  s.set_pre_routing_handler([this, catalogue, web_root](const httplib::Request& req, httplib::Response& res) {
    if (catalogue) res.set_header("Access-Control-Allow-Origin", "*");  // a public, read-only catalogue
    // Tiles are answered by the front end; those it passes on (escapes, dot
    // segments...) are answered here, before httplib would look for a static
    // file of that name and try every route's regex.
    if (ServeTile(req, res) || Screen(req, res, web_root ? &*web_root : nullptr))
      return httplib::Server::HandlerResponse::Handled;
    if (catalogue && (req.path == "/" || req.path == "/index.html")) {
      res.set_redirect("/missions.html");  // the console's first page in a catalogue is the mission picker
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });

  // Each mission's API and live events.
  AddMissionApi(
      s, P, k, [this, mission_id](const httplib::Request& req) { return registry_.Services(mission_id(req)); },
      options_, &streams_);

  s.Get(P + R"(/api/.*)", [](const httplib::Request& req, httplib::Response& res) {
    SendError(res, 404, "no such API endpoint: " + req.path + " (see server/README.md)");
  });
  if (catalogue) {
    s.Get(R"(/api/.*)", [](const httplib::Request& req, httplib::Response& res) {
      SendError(res, 404, "no such API in a catalogue: " + req.path + " (see /api/missions)");
    });
    // Each mission's operator console.
    const std::string console = options_.web_dir.empty() ? "" : options_.web_dir + "/index.html";
    s.Get(P + "/?", Guard([this, console](const httplib::Request& req, httplib::Response& res) {
            registry_.Tiles(req.matches[1]);  // 404 for an unknown or unavailable mission
            if (req.path.back() != '/') return res.set_redirect(req.path + "/");
            std::ifstream in(console, std::ios::binary);
            if (console.empty() || !in) throw ApiError(404, "no console files (--web)");
            res.set_header("Cache-Control", "no-cache");
            res.set_content(std::string(std::istreambuf_iterator<char>(in), {}), "text/html");
          }));
  }

  if (!options_.web_dir.empty()) {
    s.set_file_extension_and_mimetype_mapping("js", "text/javascript");
    s.set_file_extension_and_mimetype_mapping("mjs", "text/javascript");
    s.set_file_extension_and_mimetype_mapping("json", "application/json");
    s.set_file_extension_and_mimetype_mapping("svg", "image/svg+xml");
    // httplib refuses paths that climb out of the mount ("..", encoded or not).
    if (!s.set_mount_point("/", options_.web_dir))
      throw InputError(options_.web_dir, 0, "--web", "is not a folder with the console's files");
  }

  // Errors without a body (404 of an unknown path, 413 of a too large body...) get a JSON one.
  s.set_error_handler(httplib::Server::HandlerWithResponse([](const httplib::Request&, httplib::Response& res) {
    if (!res.body.empty()) return httplib::Server::HandlerResponse::Unhandled;
    std::string message = res.status == 404   ? "not found"
                          : res.status == 413 ? "request body too large (limit 64 KiB)"
                          : res.status == 400 ? "bad request"
                                              : "error " + std::to_string(res.status);
    res.set_content(Dump({{"error", message}}), "application/json");
    return httplib::Server::HandlerResponse::Handled;
  }));
  s.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
    std::string message = "internal error";
    try {
      std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      message = e.what();
    } catch (...) {
    }
    res.status = 500;
    res.set_content(Dump({{"error", message}}), "application/json");
  });
}

bool HttpServer::Screen(const httplib::Request& req, httplib::Response& res, const WebRoot* web_root) const {
  // (get_header_value returns a copy: kept here for the views below.)
  const std::string origin_field = req.get_header_value("Origin");
  const std::string fetch_site_field = req.get_header_value("Sec-Fetch-Site");
  const std::optional<std::string_view> origin =
      req.has_header("Origin") ? std::optional<std::string_view>(origin_field) : std::nullopt;
  // CORS for the integrations the operator allowed (--allow-origin); a
  // catalogue's answers are open to every origin already.
  if (origin && !registry_.catalogue() && origins_.Allowed(*origin)) {
    res.set_header("Access-Control-Allow-Origin", std::string(*origin));
    res.set_header("Vary", "Origin");
    res.set_header("Access-Control-Expose-Headers", "Location, X-SeaMap-Last-Seq, X-SeaMap-Records");
    if (req.method == "OPTIONS" && req.has_header("Access-Control-Request-Method")) {  // a preflight
      res.set_header("Access-Control-Allow-Methods", "GET, POST, PATCH, DELETE");
      res.set_header("Access-Control-Allow-Headers", "Authorization, Content-Type");
      res.set_header("Access-Control-Max-Age", "600");
      res.status = 204;
      return true;
    }
  }
  if (!OriginPolicy::IsSafeMethod(req.method)) {
    const std::optional<std::string_view> fetch_site =
        req.has_header("Sec-Fetch-Site") ? std::optional<std::string_view>(fetch_site_field) : std::nullopt;
    if (auto why = origins_.RefuseWrite(req.get_header_value("Host"), origin, fetch_site)) {
      SendError(res, 403, *why);
      return true;
    }
  }
  // httplib's file handler comes before the routes and follows links: a
  // link out of web/ is answered as if the file were not there.
  if (web_root && (req.method == "GET" || req.method == "HEAD") && !web_root->MayServe(req.path)) {
    SendError(res, 404, "not found");
    return true;
  }
  return false;
}

void HttpServer::Bind() {
  options_.Check();
  // httplib listens on loopback only; the front end owns the public port and answers tiles itself.
  const int backend = http_->bind_to_any_port("127.0.0.1");
  if (backend <= 0) throw InputError("", 0, "--port", "cannot open the server's loopback port");
  static_cast<BacklogServer*>(http_.get())->RaiseBacklog();
  const int loops = static_cast<int>(std::max(1u, std::min(4u, std::thread::hardware_concurrency())));
  auto tiles = [this](const std::string& mission, const std::string& path,
                      const std::optional<std::string>& if_none_match) {
    return registry_.AnswerMissionTile(mission, path, if_none_match);
  };
  front_ = std::make_unique<TileFrontEnd>(tiles, backend, loops, kMaxRequestBody);
  port_ = front_->Bind(options_.host, options_.port);
  registry_.Refresh();  // a catalogue's first listing before anyone asks (later rescans never make a request wait)
}

void HttpServer::Run() {
  try {
    http_->listen_after_bind();
  } catch (const std::exception& e) {  // e.g. its threads could not be created
    std::fprintf(stderr, "seamap: the HTTP server failed: %s\n", e.what());
    ::kill(::getpid(), SIGTERM);  // to the process: the command shuts down the way Ctrl-C does
  }
}

void HttpServer::Start() {
  thread_ = std::thread([this] { Run(); });
  for (int i = 0; i < 2500 && !http_->is_running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  if (front_) front_->Start();
}

void HttpServer::Stop() {
  registry_.CloseEvents();
  // Let open event streams send their last events before the sockets close.
  for (int i = 0; i < 100 && streams_ > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (http_) http_->stop();
  if (thread_.joinable()) thread_.join();
  // Connections passed to httplib now see it close: let them deliver what it sent.
  for (int i = 0; front_ && i < 100 && front_->proxied() > 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (front_) front_->Stop();
}

}  // namespace seamap::server
