#include "server/catalog_server.h"

#include <httplib.h>
#include <sys/socket.h>

#include <filesystem>
#include <fstream>
#include <optional>

#include <nlohmann/json.hpp>

#include "core/tiles/folder_store.h"
#include "core/util/error.h"
#include "server/api_error.h"
#include "server/http_util.h"
#include "server/mission_follow.h"
#include "server/tile_answer.h"
#include "server/tile_front_end.h"
#include "server/web_root.h"

namespace seamap::server {
namespace {

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

}  // namespace

CatalogServer::CatalogServer(ServerOptions options, std::string folder)
    : options_(std::move(options)), catalog_(std::move(folder)), http_(std::make_unique<BacklogServer>()) {
  // Each open event stream holds a thread: the pool has room for them beside the requests.
  const size_t threads = static_cast<size_t>(std::max(2, options_.threads) + std::max(1, options_.max_streams));
  http_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
  http_->set_payload_max_length(kMaxRequestBody);
  http_->set_keep_alive_max_count(10000);  // httplib's default (5) reconnects every 5 tiles
  http_->set_keep_alive_timeout(5);
  http_->set_tcp_nodelay(true);
  http_->set_socket_options([](socket_t sock) {  // no SO_REUSEPORT: a port in use must fail Bind()
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  Routes();
}

CatalogServer::~CatalogServer() {
  Stop();
}

void CatalogServer::Refresh() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool fresh = scanned_ != std::chrono::steady_clock::time_point{} &&
                       std::chrono::steady_clock::now() - scanned_ <= std::chrono::seconds(1);
    if (fresh || scanning_) return;  // one thread rescans; the others use the listing they have
    scanning_ = true;
  }
  std::vector<CatalogEntry> listing;
  try {
    listing = catalog_.Scan();  // outside mutex_: tile requests do not wait on the folder
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    scanning_ = false;
    throw;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  listing_ = std::move(listing);
  scanned_ = std::chrono::steady_clock::now();
  scanning_ = false;
}

std::vector<CatalogEntry> CatalogServer::Missions() {
  Refresh();
  std::lock_guard<std::mutex> lock(mutex_);
  return listing_;
}

const CatalogEntry& CatalogServer::MissionLocked(const std::string& id) {
  for (const CatalogEntry& e : listing_) {
    if (e.id != id) continue;
    if (!e.available) throw ApiError(404, "mission '" + id + "' is unavailable: " + e.reason);
    auto& source = sources_[e.path];
    if (!source) source = std::make_shared<TileSource>(e.path, 4, 16u << 20);
    source->SetExternalWriter(e.state == "building");  // tiles still change: short cache
    return e;
  }
  throw ApiError(404, "no mission '" + id + "' in " + catalog_.folder());
}

std::pair<CatalogEntry, std::shared_ptr<TileSource>> CatalogServer::Mission(const std::string& id) {
  Refresh();
  std::lock_guard<std::mutex> lock(mutex_);
  const CatalogEntry& e = MissionLocked(id);
  return {e, sources_[e.path]};
}

std::optional<TileAnswer> CatalogServer::AnswerMissionTile(const std::string& id, const std::string& path,
                                                           const std::optional<std::string>& if_none_match) {
  std::shared_ptr<TileSource> source;
  bool building = false;
  try {
    Refresh();
    std::lock_guard<std::mutex> lock(mutex_);  // a tile request copies no entry, only its source
    const CatalogEntry& e = MissionLocked(id);
    source = sources_[e.path];
    building = e.state == "building";
  } catch (const std::exception&) {
    return std::nullopt;  // unknown, unavailable or unreadable: httplib's route answers why
  }
  return AnswerTile(*source, building, path, if_none_match);
}

MissionServices CatalogServer::Services(const std::string& id) {
  Refresh();
  std::lock_guard<std::mutex> lock(mutex_);
  const CatalogEntry* entry = &MissionLocked(id);  // 404 for an unknown or unavailable id
  const std::shared_ptr<TileSource>& tiles = sources_[entry->path];
  std::unique_ptr<OpenMission>& open = open_[entry->path];
  if (!open) {
    auto m = std::make_unique<OpenMission>();
    try {
      m->records = OpenExistingMap(entry->path, /*writable=*/false);
      m->mission.Load(*m->records);
      m->detections = std::make_unique<DetectionRegistry>(nullptr, &m->events);  // a catalogue is read-only
      m->detections->Load(*m->records);
    } catch (const std::exception& e) {
      throw ApiError(404, "mission '" + id + "' cannot be read: " + e.what());
    }
    // The dive's file name where the map has only the default name.
    m->mission.SetName(entry->name == "seamap mission" ? std::filesystem::path(entry->path).stem().string()
                                                       : entry->name);
    m->mission.SetLayers(tiles->Layers(), tiles->Format());
    m->mission.SetAccess(!options_.token.empty(), false);
    Progress p = m->mission.progress();
    p.state = m->state = entry->state;
    m->mission.SetProgress(p);
    open = std::move(m);
  }
  return {&open->mission, open->detections.get(), &open->events};
}

void CatalogServer::Follow() {
  Refresh();
  // Which open missions to follow, under the lock; their files are read outside
  // it, so tile requests do not wait on SQLite (open missions are never closed).
  std::vector<std::pair<OpenMission*, CatalogEntry>> follow;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const CatalogEntry& e : listing_) {
      auto it = open_.find(e.path);
      if (it != open_.end() && e.available) follow.push_back({it->second.get(), e});
    }
  }
  for (auto& [m, e] : follow) {
    try {
      m->detections->Refresh(*m->records);
      if (e.state != "building" && m->state != "building") continue;
      FollowRecords(m->mission, m->events, *m->records, e.state, "");
      m->state = e.state;  // only this thread changes it after the mission is opened
    } catch (const std::exception& ex) {
      std::fprintf(stderr, "warning: cannot follow %s: %s\n", e.path.c_str(), ex.what());
    }
  }
}

void CatalogServer::Routes() {
  httplib::Server& s = *http_;
  s.Get("/api/missions", Guard([this](const httplib::Request&, httplib::Response& res) {
          nlohmann::json list = nlohmann::json::array();
          for (const auto& e : Missions()) list.push_back(EntryJson(e));
          res.set_header("Cache-Control", "no-cache");
          SendJson(res, list);
        }));
  s.Get(R"(/missions/([a-z0-9_-]+)/tiles(/[a-z0-9_]{1,32})?\.json)",
        Guard([this](const httplib::Request& req, httplib::Response& res) {
          auto [entry, tiles] = Mission(req.matches[1]);
          const std::string layer = req.matches[2].length() > 0 ? std::string(req.matches[2]).substr(1) : "";
          if (!layer.empty() && !tiles->IsLayer(layer)) throw ApiError(404, "no layer '" + layer + "'");
          std::map<std::string, std::string> metadata = tiles->Metadata(layer);
          for (auto it = metadata.begin(); it != metadata.end();)
            it = it->first.rfind("layer.", 0) == 0 ? metadata.erase(it) : std::next(it);
          nlohmann::json j = MetadataToTileJson(metadata, tiles->Format());
          const std::string host = req.has_header("Host") ? req.get_header_value("Host") : "127.0.0.1";
          j["tiles"] = {"http://" + host + "/missions/" + entry.id + "/tiles/" + (layer.empty() ? "" : layer + "/") +
                        "{z}/{x}/{y}." + tiles->Format()};
          if (!j.contains("name")) j["name"] = entry.name;
          j["seamap_layers"] = tiles->Layers();
          res.set_header("Cache-Control", "no-cache");
          SendJson(res, j);
        }));
  s.Get(R"(/missions/([a-z0-9_-]+)/tiles/(.+))", Guard([this](const httplib::Request& req, httplib::Response& res) {
          auto [entry, tiles] = Mission(req.matches[1]);
          std::optional<std::string> if_none_match;
          if (req.has_header("If-None-Match")) if_none_match = req.get_header_value("If-None-Match");
          TileAnswer a = AnswerTile(*tiles, entry.state == "building", std::string(req.matches[2]), if_none_match);
          res.status = a.status;
          for (const auto& [name, value] : a.headers) res.set_header(name, value);
          if (a.body) res.set_content(a.body->data(), a.body->size(), a.content_type.c_str());
        }));
  // Each mission's API and live events, and its operator console.
  AddMissionApi(
      s, kMissionPrefix, 1, [this](const httplib::Request& req) { return Services(req.matches[1]); }, options_,
      &streams_);
  s.Get(std::string(kMissionPrefix) + R"(/api/.*)", [](const httplib::Request& req, httplib::Response& res) {
    SendJson(res, {{"error", "no such API endpoint: " + req.path + " (see server/README.md)"}}, 404);
  });
  s.Get(R"(/api/.*)", [](const httplib::Request& req, httplib::Response& res) {
    SendJson(res, {{"error", "no such API in a catalogue: " + req.path + " (see /api/missions)"}}, 404);
  });
  const std::string console = options_.web_dir.empty() ? "" : options_.web_dir + "/index.html";
  s.Get(std::string(kMissionPrefix) + "/?", Guard([this, console](const httplib::Request& req, httplib::Response& res) {
          Mission(req.matches[1]);  // 404 for an unknown or unavailable mission
          if (req.path.back() != '/') return res.set_redirect(req.path + "/");
          std::ifstream in(console, std::ios::binary);
          if (console.empty() || !in) throw ApiError(404, "no console files (--web)");
          res.set_header("Cache-Control", "no-cache");
          res.set_content(std::string(std::istreambuf_iterator<char>(in), {}), "text/html");
        }));
  // The console's first page in a catalogue is the mission picker.
  std::optional<WebRoot> web_root;
  if (!options_.web_dir.empty()) web_root.emplace(options_.web_dir);
  s.set_pre_routing_handler([web_root](const httplib::Request& req, httplib::Response& res) {
    res.set_header("Access-Control-Allow-Origin", "*");  // a public, read-only catalogue
    // httplib's file handler follows links: one out of web/ is not there.
    if (web_root && (req.method == "GET" || req.method == "HEAD") && !web_root->MayServe(req.path)) {
      SendJson(res, {{"error", "not found"}}, 404);
      return httplib::Server::HandlerResponse::Handled;
    }
    if (req.path != "/" && req.path != "/index.html") return httplib::Server::HandlerResponse::Unhandled;
    res.set_redirect("/missions.html");
    return httplib::Server::HandlerResponse::Handled;
  });
  if (!options_.web_dir.empty()) {
    s.set_file_extension_and_mimetype_mapping("js", "text/javascript");
    s.set_file_extension_and_mimetype_mapping("json", "application/json");
    if (!s.set_mount_point("/", options_.web_dir))
      throw InputError(options_.web_dir, 0, "--web", "is not a folder with the console's files");
  }
}

void CatalogServer::Bind() {
  options_.Check();
  // httplib listens on loopback only; the front end owns the public port and answers tiles itself.
  const int backend = http_->bind_to_any_port("127.0.0.1");
  if (backend <= 0) throw InputError("", 0, "--port", "cannot open the server's loopback port");
  static_cast<BacklogServer*>(http_.get())->RaiseBacklog();
  const int loops = static_cast<int>(std::max(1u, std::min(4u, std::thread::hardware_concurrency())));
  front_ = std::make_unique<TileFrontEnd>(
      [this](const std::string& id, const std::string& path, const std::optional<std::string>& if_none_match) {
        return id.empty() ? std::nullopt : AnswerMissionTile(id, path, if_none_match);
      },
      backend, loops, kMaxRequestBody);
  port_ = front_->Bind(options_.host, options_.port);
  Refresh();  // the first listing before anyone asks (later rescans never make a request wait)
}

void CatalogServer::Start() {
  thread_ = std::thread([this] { http_->listen_after_bind(); });
  for (int i = 0; i < 2500 && !http_->is_running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  front_->Start();
}

void CatalogServer::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto& [path, open] : open_) open->events.Close();
  }
  // Let open event streams send their last events before the sockets close.
  for (int i = 0; i < 100 && streams_ > 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (http_) http_->stop();
  if (thread_.joinable()) thread_.join();
  for (int i = 0; front_ && i < 100 && front_->proxied() > 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (front_) front_->Stop();
}

}  // namespace seamap::server
