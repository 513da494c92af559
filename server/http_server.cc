#include "server/http_server.h"

#include <httplib.h>

#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "core/tiles/folder_store.h"
#include "core/util/error.h"
#include "server/api_error.h"
#include "server/http_util.h"
#include "server/mission_api.h"
#include "server/tile_answer.h"
#include "server/web_root.h"

namespace seamap::server {

HttpServer::HttpServer(ServerOptions options, TileSource* tiles, MissionState* mission, DetectionRegistry* detections,
                       EventHub* events)
    : options_(std::move(options)),
      origins_(options_.allow_origins),
      tiles_(tiles),
      mission_(mission),
      detections_(detections),
      events_(events),
      http_(std::make_unique<BacklogServer>()) {
  const size_t threads = static_cast<size_t>(std::max(2, options_.threads) + std::max(1, options_.max_streams));
  http_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  http_->set_payload_max_length(kMaxRequestBody);
  http_->set_keep_alive_max_count(10000);
  http_->set_keep_alive_timeout(5);
  http_->set_tcp_nodelay(true);
  // httplib's default options add SO_REUSEPORT, with which a second server binds
  // the same port and silently takes half the connections. SO_REUSEADDR alone
  // still allows a quick restart, and a port in use fails Bind() as it should.
  http_->set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  mission_->SetAccess(!options_.token.empty(), detections_->writable());
  Routes();
}

HttpServer::~HttpServer() {
  Stop();
}

void HttpServer::Routes() {
  httplib::Server& s = *http_;

  auto tilejson = [this](const httplib::Request& req, httplib::Response& res, const std::string& layer) {
    if (!layer.empty() && !tiles_->IsLayer(layer)) throw ApiError(404, "no layer '" + layer + "'");
    const std::string ext = tiles_->Format();
    std::map<std::string, std::string> metadata = tiles_->Metadata(layer);
    for (auto it = metadata.begin(); it != metadata.end();)  // other layers' keys stay in their own TileJSON
      it = it->first.rfind("layer.", 0) == 0 ? metadata.erase(it) : std::next(it);
    nlohmann::json j = MetadataToTileJson(metadata, ext);
    const std::string host = req.has_header("Host") ? req.get_header_value("Host") : "127.0.0.1";
    j["tiles"] = {"http://" + host + "/tiles/" + (layer.empty() ? "" : layer + "/") + "{z}/{x}/{y}." + ext};
    if (!j.contains("name")) j["name"] = "SeaMap mission";
    if (!j.contains("attribution")) j["attribution"] = "";
    j["seamap_layers"] = tiles_->Layers();
    j["seamap_formats"] = tiles_->Formats();  // the stored format first, then what it is also served as
    res.set_header("Access-Control-Allow-Origin", "*");
    res.set_header("Cache-Control", "no-cache");
    SendJson(res, j);
  };
  s.Get("/tiles.json",
        Guard([tilejson](const httplib::Request& req, httplib::Response& res) { tilejson(req, res, ""); }));
  s.Get(R"(/tiles/([a-z0-9_]{1,32})\.json)",
        Guard([tilejson](const httplib::Request& req, httplib::Response& res) { tilejson(req, res, req.matches[1]); }));

  // Tiles are most of the traffic: answered before httplib's routing, which
  // would first look for a static file of that name and then try every route's regex.
  auto serve_tile = [this](const httplib::Request& req, httplib::Response& res) {
    std::optional<std::string> if_none_match;
    if (req.has_header("If-None-Match")) if_none_match = req.get_header_value("If-None-Match");
    TileAnswer a = AnswerTile(*tiles_, mission_->building(), req.path.substr(7), if_none_match);  // after "/tiles/"
    res.status = a.status;
    for (const auto& [name, value] : a.headers) res.set_header(name, value);
    if (a.body) res.set_content(a.body->data(), a.body->size(), a.content_type.c_str());
  };
  std::optional<WebRoot> web_root;
  if (!options_.web_dir.empty()) web_root.emplace(options_.web_dir);
  s.set_pre_routing_handler([this, serve_tile, web_root](const httplib::Request& req, httplib::Response& res) {
    const bool is_tile = (req.method == "GET" || req.method == "HEAD") && req.path.rfind("/tiles/", 0) == 0 &&
                         !(req.path.size() > 5 && req.path.compare(req.path.size() - 5, 5, ".json") == 0);
    if (is_tile) {
      serve_tile(req, res);
      return httplib::Server::HandlerResponse::Handled;
    }
    return Screen(req, res, web_root ? &*web_root : nullptr) ? httplib::Server::HandlerResponse::Handled
                                                             : httplib::Server::HandlerResponse::Unhandled;
  });

  AddMissionApi(
      s, "", 0,
      [this](const httplib::Request&) {
        return MissionServices{mission_, detections_, events_};
      },
      options_, &streams_);

  s.Get(R"(/api/.*)", [](const httplib::Request& req, httplib::Response& res) {
    SendError(res, 404, "no such API endpoint: " + req.path + " (see server/README.md)");
  });

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
  // CORS for the integrations the operator allowed (--allow-origin).
  if (origin && origins_.Allowed(*origin)) {
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
  // httplib listens on loopback only; the front end owns the public port.
  const int backend = http_->bind_to_any_port("127.0.0.1");
  if (backend <= 0) throw InputError("", 0, "--port", "cannot open the server's loopback port");
  static_cast<BacklogServer*>(http_.get())->RaiseBacklog();
  const int loops = static_cast<int>(std::max(1u, std::min(4u, std::thread::hardware_concurrency())));
  auto tiles = [this](const std::string& mission, const std::string& path,
                      const std::optional<std::string>& if_none_match) -> std::optional<TileAnswer> {
    if (!mission.empty()) return std::nullopt;  // a catalogue's path: the backend's 404
    return AnswerTile(*tiles_, mission_->building(), path, if_none_match);
  };
  front_ = std::make_unique<TileFrontEnd>(tiles, backend, loops, kMaxRequestBody);
  port_ = front_->Bind(options_.host, options_.port);
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
  events_->Close();
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
