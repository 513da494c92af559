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
#include "server/event_filter.h"
#include "server/gzip_stream.h"
#include "server/photo_preview.h"
#include "server/tile_answer.h"
#include "server/track_feature.h"
#include "server/utf8.h"
#include "server/web_root.h"

namespace seamap::server {
namespace {

constexpr size_t kMaxBody = 64 * 1024;

// httplib 0.11 listens with a backlog of 5: a burst of new connections (a
// browser opening six, a load test opening 64) overflows it and the kernel
// drops SYNs, which clients retry only after a second. Calling listen() again
// on the bound socket raises the backlog.
class BacklogServer : public httplib::Server {
 public:
  void RaiseBacklog() { ::listen(svr_sock_, SOMAXCONN); }
};
constexpr auto kKeepAliveComment = std::chrono::seconds(15);

// Messages quote what clients sent, which need not be UTF-8: such bytes
// become U+FFFD instead of a 500 from the JSON library.
std::string Dump(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void SendJson(httplib::Response& res, const nlohmann::json& j, int status = 200) {
  res.status = status;
  res.set_content(Dump(j), "application/json");
}

void SendError(httplib::Response& res, int status, const std::string& message) {
  SendJson(res, {{"error", message}}, status);
}

std::optional<std::string> Param(const httplib::Request& req, const char* name) {
  if (!req.has_param(name)) return std::nullopt;
  return req.get_param_value(name);
}

int64_t ParseId(const std::string& text, const char* what) {
  try {
    size_t used = 0;
    long long v = std::stoll(text, &used);
    if (used == text.size() && v >= 0) return v;
  } catch (const std::exception&) {
  }
  throw ApiError(400, std::string(what) + ": expected a non-negative integer, got '" + text + "'");
}

double ParseCoordinate(const httplib::Request& req, const char* name, double lo, double hi) {
  auto v = Param(req, name);
  if (!v) throw ApiError(400, std::string("parameter '") + name + "' is required");
  try {
    size_t used = 0;
    double d = std::stod(*v, &used);
    if (used == v->size() && d >= lo && d <= hi) return d;
  } catch (const std::exception&) {
  }
  throw ApiError(400, std::string("parameter '") + name + "': expected a number in [" + std::to_string(int(lo)) + ", " +
                          std::to_string(int(hi)) + "], got '" + *v + "'");
}

nlohmann::json ParseBody(const httplib::Request& req) {
  if (auto bad = FirstInvalidUtf8(req.body)) {
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>(req.body[*bad]));
    throw ApiError(400, "body: not valid UTF-8 (byte " + std::string(byte) + " at offset " + std::to_string(*bad) +
                            "); JSON must be UTF-8 (RFC 8259)");
  }
  try {
    return nlohmann::json::parse(req.body);
  } catch (const nlohmann::json::exception& e) {
    throw ApiError(400, std::string("body: expected JSON: ") + e.what());
  }
}

// Runs a handler, turning ApiError and other exceptions into JSON errors.
template <typename F>
httplib::Server::Handler Guard(F f) {
  return [f](const httplib::Request& req, httplib::Response& res) {
    try {
      f(req, res);
    } catch (const ApiError& e) {
      SendError(res, e.status(), e.what());
    } catch (const std::exception& e) {
      SendError(res, 500, e.what());
    }
  };
}

// Does the request carry "Authorization: Bearer <token>"? (Always, without a token.)
bool Authorized(const httplib::Request& req, const std::string& token) {
  if (token.empty()) return true;
  const std::string header = req.get_header_value("Authorization");
  const std::string expected = "Bearer " + token;
  if (header.size() != expected.size()) return false;
  unsigned char diff = 0;  // constant time: do not leak the token through timing
  for (size_t i = 0; i < header.size(); ++i) diff |= header[i] ^ expected[i];
  return diff == 0;
}

// How one event stream is cut to the client's needs (see server/README.md).
struct StreamSettings {
  EventFilter filter;
  std::chrono::milliseconds batch{0};  // gather events this long into one write
  bool coalesce = false;               // drop superseded tile/pose/progress events of a batch
  std::chrono::milliseconds heartbeat = kKeepAliveComment;
  bool ping = false;  // an event the browser sees, not a comment
};

StreamSettings ParseStreamSettings(const httplib::Request& req) {
  StreamSettings s;
  s.filter = EventFilter::Parse(Param(req, "types"), Param(req, "layers"), Param(req, "zoom"), Param(req, "bbox"));
  if (auto v = Param(req, "batch_ms")) {
    const int64_t ms = ParseId(*v, "parameter 'batch_ms'");
    if (ms > 10000) throw ApiError(400, "parameter 'batch_ms': expected 0..10000 milliseconds, got " + *v);
    s.batch = std::chrono::milliseconds(ms);
    s.coalesce = ms > 0;
  }
  if (auto v = Param(req, "heartbeat_s")) {
    const int64_t sec = ParseId(*v, "parameter 'heartbeat_s'");
    if (sec < 1 || sec > 60) throw ApiError(400, "parameter 'heartbeat_s': expected 1..60 seconds, got " + *v);
    s.heartbeat = std::chrono::seconds(sec);
    s.ping = true;
  }
  return s;
}

}  // namespace

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
  http_->set_payload_max_length(kMaxBody);
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

  s.Get("/api/status", Guard([this](const httplib::Request&, httplib::Response& res) {
          nlohmann::json j = mission_->StatusJson();
          j["event_seq"] = events_->LastId();
          j["classes"] = detections_->Classes();  // modem record class ids
          res.set_header("Cache-Control", "no-cache");
          SendJson(res, j);
        }));

  s.Get("/api/keyframes",
        Guard([this](const httplib::Request&, httplib::Response& res) { SendJson(res, mission_->KeyframesJson()); }));
  s.Get("/api/track", Guard([this](const httplib::Request& req, httplib::Response& res) {
          const TrackSource source = ParseTrackSource(Param(req, "source"));
          int since = 0;
          if (auto v = Param(req, "since"))
            since = static_cast<int>(std::min<int64_t>(ParseId(*v, "parameter 'since'"), INT_MAX));
          // Start at the point the client already has, so the new piece joins the line.
          const int from = std::max(0, since - 1);
          res.set_header("Cache-Control", "no-cache");
          if (source == TrackSource::kBuoy) {
            SendJson(res, TrackFeature(mission_->BuoyTrackFrom(from), source, mission_->BuoyTrackSize(), false));
            return;
          }
          SendJson(res, TrackFeature(mission_->TrackFrom(from), source, mission_->TrackSize(),
                                     mission_->TrajectoryCorrected()));
        }));

  s.Get("/api/frames", Guard([this](const httplib::Request& req, httplib::Response& res) {
          const double lat = ParseCoordinate(req, "lat", -90, 90);
          const double lon = ParseCoordinate(req, "lon", -180, 180);
          size_t limit = 50;
          if (auto v = Param(req, "limit"))
            limit = std::max<int64_t>(1, std::min<int64_t>(1000, ParseId(*v, "parameter 'limit'")));
          nlohmann::json frames = nlohmann::json::array();
          for (const auto& f : mission_->FramesCovering({lat, lon}, limit)) frames.push_back(FrameJson(f));
          SendJson(res, {{"frames", frames}});
        }));

  s.Get("/api/footprints", Guard([this](const httplib::Request& req, httplib::Response& res) {
          auto bbox = Param(req, "bbox");
          if (!bbox) throw ApiError(400, "parameter 'bbox' is required (west,south,east,north)");
          const EventFilter area = EventFilter::Parse(std::nullopt, std::nullopt, std::nullopt, bbox);
          size_t limit = 2000;
          if (auto v = Param(req, "limit"))
            limit = std::max<int64_t>(1, std::min<int64_t>(20000, ParseId(*v, "parameter 'limit'")));
          nlohmann::json features = nlohmann::json::array();
          for (const auto& f : mission_->FramesMeeting(*area.bbox, limit)) features.push_back(FootprintFeature(f));
          res.set_header("Cache-Control", "no-cache");
          SendJson(res, {{"type", "FeatureCollection"}, {"features", features}});
        }));

  s.Get(R"(/api/frames/([^/]+))", Guard([this](const httplib::Request& req, httplib::Response& res) {
          const int64_t id = ParseId(req.matches[1], "frame id");
          auto f = id > INT_MAX ? std::nullopt : mission_->Frame(static_cast<int>(id));
          if (!f) throw ApiError(404, "no frame " + std::to_string(id));
          SendJson(res, FrameJson(*f));
        }));

  s.Get(R"(/api/frames/([^/]+)/image)", Guard([this](const httplib::Request& req, httplib::Response& res) {
          const int64_t id = ParseId(req.matches[1], "frame id");
          auto f = id > INT_MAX ? std::nullopt : mission_->Frame(static_cast<int>(id));
          if (!f) throw ApiError(404, "no frame " + std::to_string(id));
          int max_side = 0;
          if (auto v = Param(req, "max"))
            max_side = static_cast<int>(std::min<int64_t>(8192, ParseId(*v, "parameter 'max'")));
          std::string path = f->image_path;
          std::error_code ec;
          if (!options_.photo_dir.empty() && (path.empty() || !std::filesystem::is_regular_file(path, ec)))
            path = (std::filesystem::path(options_.photo_dir) / f->image).string();
          auto photo = LoadPhoto(path, max_side);
          if (!photo) throw ApiError(404, "photo of frame " + std::to_string(id) + " cannot be read: " + path);
          res.set_header("Cache-Control", "public, max-age=3600");
          res.set_content(photo->bytes, photo->content_type.c_str());
        }));

  auto detection_filter = [](const httplib::Request& req) {
    return ParseDetectionFilter(Param(req, "bbox"), Param(req, "class"), Param(req, "min_score"), Param(req, "since"),
                                Param(req, "status"), Param(req, "source"));
  };
  s.Get("/api/detections", Guard([this, detection_filter](const httplib::Request& req, httplib::Response& res) {
          DetectionFilter f = detection_filter(req);
          res.set_header("Cache-Control", "no-cache");
          SendJson(res, detections_->Query(f));
        }));
  // 24-byte records for an acoustic modem (docs/MODEM_RECORD.md).
  s.Get("/api/detections.bin", Guard([this, detection_filter](const httplib::Request& req, httplib::Response& res) {
          DetectionFilter f = detection_filter(req);
          size_t max = SIZE_MAX;
          if (auto v = Param(req, "max")) max = static_cast<size_t>(ParseId(*v, "parameter 'max'"));
          const PackedDetections packed = detections_->Pack(f, max, mission_->T0());
          res.set_header("Cache-Control", "no-cache");
          res.set_header("X-SeaMap-Last-Seq", std::to_string(packed.last_seq));
          res.set_header("X-SeaMap-Records", std::to_string(packed.count));
          res.set_content(std::string(packed.bytes.begin(), packed.bytes.end()), "application/octet-stream");
        }));
  s.Get(R"(/api/detections/([^/]+))", Guard([this](const httplib::Request& req, httplib::Response& res) {
          const int64_t id = ParseId(req.matches[1], "detection id");
          auto d = detections_->Get(id);
          if (!d) throw ApiError(404, "no detection " + std::to_string(id));
          SendJson(res, *d);
        }));

  auto require_token = [this](const httplib::Request& req, httplib::Response& res) {
    if (Authorized(req, options_.token)) return true;
    res.set_header("WWW-Authenticate", "Bearer realm=\"seamap\"");
    SendError(res, 401,
              req.has_header("Authorization")
                  ? "wrong token: 'Authorization: Bearer TOKEN' must give the server's --token"
                  : "writing needs 'Authorization: Bearer TOKEN' (the server's --token)");
    return false;
  };
  // The console checks a token as soon as it is entered, before any write.
  s.Get("/api/auth", Guard([require_token](const httplib::Request& req, httplib::Response& res) {
          res.set_header("Cache-Control", "no-store");
          if (require_token(req, res)) res.status = 204;
        }));
  s.Post("/api/detections", Guard([this, require_token](const httplib::Request& req, httplib::Response& res) {
           if (!require_token(req, res)) return;
           nlohmann::json feature = detections_->Create(ParseBody(req));
           res.set_header("Location", "/api/detections/" + std::to_string(feature["id"].get<int64_t>()));
           SendJson(res, feature, 201);
         }));
  s.Patch(R"(/api/detections/([^/]+))",
          Guard([this, require_token](const httplib::Request& req, httplib::Response& res) {
            if (!require_token(req, res)) return;
            const int64_t id = ParseId(req.matches[1], "detection id");
            SendJson(res, detections_->Update(id, ParseBody(req)));
          }));
  s.Delete(R"(/api/detections/([^/]+))",
           Guard([this, require_token](const httplib::Request& req, httplib::Response& res) {
             if (!require_token(req, res)) return;
             detections_->Delete(ParseId(req.matches[1], "detection id"));
             res.status = 204;
           }));

  s.Get("/api/events", [this](const httplib::Request& req, httplib::Response& res) {
    // Bad parameters are refused before the stream counts against the cap.
    StreamSettings settings;
    try {
      settings = ParseStreamSettings(req);
    } catch (const ApiError& e) {
      SendError(res, e.status(), e.what());
      return;
    }
    if (streams_.fetch_add(1) >= options_.max_streams) {
      streams_.fetch_sub(1);
      res.set_header("Retry-After", "10");
      SendError(res, 503, "too many event streams open (limit " + std::to_string(options_.max_streams) + ")");
      return;
    }
    uint64_t cursor = events_->LastId();
    // after=ID opens a stream with other filters where the last one stopped;
    // the browser's own reconnect of it sends Last-Event-ID too, which is later.
    std::optional<uint64_t> resume;
    for (const std::string& text : {req.get_header_value("Last-Event-ID"), Param(req, "after").value_or("")}) {
      try {
        if (!text.empty()) resume = std::max(resume.value_or(0), static_cast<uint64_t>(std::stoull(text)));
      } catch (const std::exception&) {
      }
    }
    if (resume && *resume <= cursor) cursor = *resume;  // a later id comes from an earlier server run
    auto position = std::make_shared<uint64_t>(cursor);
    auto greeted = std::make_shared<bool>(false);
    std::shared_ptr<GzipStream> gzip;
    if (AcceptsGzip(req.get_header_value("Accept-Encoding"))) {
      gzip = std::make_shared<GzipStream>();
      res.set_header("Content-Encoding", "gzip");
      res.set_header("Vary", "Accept-Encoding");
    }
    res.set_header("Cache-Control", "no-cache");
    res.set_header("X-Accel-Buffering", "no");
    res.set_chunked_content_provider(
        "text/event-stream",
        [this, position, greeted, gzip, settings](size_t, httplib::DataSink& sink) {
          auto send = [&](const std::string& text) {
            if (!gzip) return sink.write(text.data(), text.size());
            const std::string packed = gzip->Write(text);
            return sink.write(packed.data(), packed.size());
          };
          if (!*greeted) {
            *greeted = true;
            return send("retry: 2000\n: seamap events\n\n");
          }
          auto events = events_->WaitAfter(*position, settings.heartbeat);
          if (!events.empty() && settings.batch.count() > 0 && !events_->closed()) {
            // Gather what comes in the next moments into one write (and one coalesced batch).
            std::this_thread::sleep_for(settings.batch);
            events = events_->WaitAfter(*position, std::chrono::milliseconds(0));
          }
          if (!events.empty()) *position = events.back().id;
          std::string out;
          std::vector<Event> kept;
          for (Event& e : events)
            if (settings.filter.Keep(e)) kept.push_back(std::move(e));
          if (settings.coalesce) kept = Coalesce(std::move(kept));
          for (const Event& e : kept) out += FormatEvent(e);
          if (events_->closed()) {  // shutting down: deliver the last events (e.g. "complete"), then end
            if (!out.empty()) send(out);
            if (gzip) {
              const std::string tail = gzip->Finish();
              sink.write(tail.data(), tail.size());
            }
            sink.done();
            return true;
          }
          if (out.empty() && !events.empty()) return true;  // all filtered out: wait for the next
          if (out.empty())
            out = settings.ping ? "event: ping\ndata: {\"last_id\":" + std::to_string(*position) + "}\n\n"
                                : ": keep-alive\n\n";
          return send(out);
        },
        [this](bool) { streams_.fetch_sub(1); });
  });

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
  front_ = std::make_unique<TileFrontEnd>(tiles_, mission_, backend, loops, kMaxBody);
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
