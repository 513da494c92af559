#include "server/mission_api.h"

#include <httplib.h>

#include <chrono>
#include <climits>
#include <filesystem>
#include <memory>
#include <thread>

#include "server/event_filter.h"
#include "server/http/gzip_stream.h"
#include "server/http/http_util.h"
#include "server/photo_preview.h"
#include "server/track_feature.h"

namespace seamap::server {
namespace {

constexpr auto kKeepAliveComment = std::chrono::seconds(15);
// GET /api/detections answers at most this many features (about 4 MB), then `next`.
constexpr size_t kDetectionsPerPage = 5000;
// Photos read at once, and how long a request waits for its turn: slow disks
// or hostile files never hold every server thread (server/photo_preview.h).
constexpr int kPhotoSlots = 4;
constexpr auto kPhotoWait = std::chrono::seconds(5);

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

void AddMissionApi(httplib::Server& s, const std::string& prefix, int prefix_groups, MissionResolver resolve,
                   const ServerOptions& options, std::atomic<int>* streams) {
  const std::string& P = prefix;
  const int k = prefix_groups;  // the routes' own captures come after the prefix's
  s.Get(P + "/api/status", Guard([resolve](const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          nlohmann::json j = m.mission->StatusJson();
          j["event_seq"] = m.events->LastId();
          j["classes"] = m.detections->Classes();  // modem record class ids
          // Records the map holds but nobody can read (NaN boxes...): left out, and said so.
          if (const int64_t n = m.detections->Unreadable(); n > 0) j["unreadable_detections"] = n;
          res.set_header("Cache-Control", "no-cache");
          SendJson(res, j);
        }));

  // The operator's "how deep is it there?" (server/terrain_query.h).
  s.Get(P + "/api/terrain", Guard([resolve](const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          const double lat = ParseCoordinate(req, "lat", -90, 90), lon = ParseCoordinate(req, "lon", -180, 180);
          SendJson(res, m.mission->TerrainAt({lat, lon}));
        }));
  s.Get(P + "/api/keyframes", Guard([resolve](const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          SendJson(res, m.mission->KeyframesJson());
        }));
  s.Get(P + "/api/track", Guard([resolve](const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          const TrackSource source = ParseTrackSource(Param(req, "source"));
          int since = 0;
          if (auto v = Param(req, "since"))
            since = static_cast<int>(std::min<int64_t>(ParseId(*v, "parameter 'since'"), INT_MAX));
          // Start at the point the client already has, so the new piece joins the line.
          const int from = std::max(0, since - 1);
          res.set_header("Cache-Control", "no-cache");
          if (source == TrackSource::kBuoy) {
            SendJson(res, TrackFeature(m.mission->BuoyTrackFrom(from), source, m.mission->BuoyTrackSize(), false));
            return;
          }
          if (source == TrackSource::kRefined && m.mission->PlacedTrajectory() != TrajectorySource::kRefined)
            throw ApiError(404, std::string("source 'refined': this mission's trajectory was not refined (its frames "
                                            "were placed with the ") +
                                    (m.mission->PlacedTrajectory() == TrajectorySource::kNav
                                         ? "navigation as given"
                                         : "navigation filter's estimate, source 'estimated'") +
                                    "; build --refine-nav refines it)");
          SendJson(res, TrackFeature(m.mission->TrackFrom(from), source, m.mission->TrackSize(),
                                     m.mission->TrajectoryCorrected()));
        }));

  s.Get(P + "/api/frames", Guard([resolve](const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          const double lat = ParseCoordinate(req, "lat", -90, 90);
          const double lon = ParseCoordinate(req, "lon", -180, 180);
          size_t limit = 50;
          if (auto v = Param(req, "limit"))
            limit = std::max<int64_t>(1, std::min<int64_t>(1000, ParseId(*v, "parameter 'limit'")));
          nlohmann::json frames = nlohmann::json::array();
          for (const auto& f : m.mission->FramesCovering({lat, lon}, limit)) frames.push_back(FrameJson(f));
          SendJson(res, {{"frames", frames}});
        }));

  s.Get(P + "/api/footprints", Guard([resolve](const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          auto bbox = Param(req, "bbox");
          if (!bbox) throw ApiError(400, "parameter 'bbox' is required (west,south,east,north)");
          const EventFilter area = EventFilter::Parse(std::nullopt, std::nullopt, std::nullopt, bbox);
          size_t limit = 2000;
          if (auto v = Param(req, "limit"))
            limit = std::max<int64_t>(1, std::min<int64_t>(20000, ParseId(*v, "parameter 'limit'")));
          nlohmann::json features = nlohmann::json::array();
          for (const auto& f : m.mission->FramesMeeting(*area.bbox, limit)) features.push_back(FootprintFeature(f));
          res.set_header("Cache-Control", "no-cache");
          SendJson(res, {{"type", "FeatureCollection"}, {"features", features}});
        }));

  s.Get(P + R"(/api/frames/([^/]+))", Guard([resolve, k](const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          const int64_t id = ParseId(req.matches[k + 1], "frame id");
          auto f = id > INT_MAX ? std::nullopt : m.mission->Frame(static_cast<int>(id));
          if (!f) throw ApiError(404, "no frame " + std::to_string(id));
          SendJson(res, FrameJson(*f));
        }));

  s.Get(P + R"(/api/frames/([^/]+)/image)",
        Guard([resolve, k, photo_dir = options.photo_dir, gate = std::make_shared<PhotoGate>(kPhotoSlots)](
                  const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          const int64_t id = ParseId(req.matches[k + 1], "frame id");
          auto f = id > INT_MAX ? std::nullopt : m.mission->Frame(static_cast<int>(id));
          if (!f) throw ApiError(404, "no frame " + std::to_string(id));
          int max_side = 0;
          if (auto v = Param(req, "max"))
            max_side = static_cast<int>(std::min<int64_t>(8192, ParseId(*v, "parameter 'max'")));
          const std::string what = "photo of frame " + std::to_string(id) + " cannot be read: ";
          std::string problem;
          const std::optional<std::string> path = ResolvePhoto(*f, {m.mission->PhotoFolder(), photo_dir}, &problem);
          if (!path) throw ApiError(404, what + f->image_path.substr(0, 100) + ": " + problem);
          if (!gate->Enter(kPhotoWait)) {
            res.set_header("Retry-After", "5");
            throw ApiError(503, "too many photos being read; ask again");
          }
          std::optional<Photo> photo;
          try {
            photo = LoadPhoto(*path, max_side, &problem);
          } catch (...) {
            gate->Leave();
            throw;
          }
          gate->Leave();
          if (!photo) throw ApiError(404, what + path->substr(0, 100) + ": " + problem);
          res.set_header("Cache-Control", "public, max-age=3600");
          res.set_content(photo->bytes, photo->content_type.c_str());
        }));

  auto detection_filter = [](const httplib::Request& req) {
    return ParseDetectionFilter(Param(req, "bbox"), Param(req, "class"), Param(req, "min_score"), Param(req, "since"),
                                Param(req, "status"), Param(req, "source"));
  };
  // Paged: a recogniser run wild stored 232,362 objects, a 188 MB answer that
  // took the server to 4.1 GB; a page holds at most kDetectionsPerPage and
  // `next` is the URL of the following one (the same filter, after=ITS_LAST_ID).
  s.Get(P + "/api/detections", Guard([resolve, detection_filter](const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          DetectionFilter f = detection_filter(req);
          size_t limit = kDetectionsPerPage;
          if (auto v = Param(req, "limit")) {
            const int64_t n = ParseId(*v, "parameter 'limit'");
            if (n < 1 || n > static_cast<int64_t>(kDetectionsPerPage))
              throw ApiError(400, "parameter 'limit': expected 1.." + std::to_string(kDetectionsPerPage) +
                                      " detections per page, got " + *v);
            limit = static_cast<size_t>(n);
          }
          std::optional<int64_t> after;
          if (auto v = Param(req, "after")) after = ParseId(*v, "parameter 'after'");
          bool more = false;
          nlohmann::json page = m.detections->QueryPage(f, after, limit, &more);
          if (more) {
            httplib::Params next = req.params;
            next.erase("after");
            next.emplace("after", std::to_string(page["features"].back()["id"].get<int64_t>()));
            page["next"] = req.path + "?" + httplib::detail::params_to_query_str(next);
          }
          res.set_header("Cache-Control", "no-cache");
          SendJson(res, page);
        }));
  // 24-byte records for an acoustic modem (docs/MODEM_RECORD.md).
  s.Get(P + "/api/detections.bin",
        Guard([resolve, detection_filter](const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          DetectionFilter f = detection_filter(req);
          size_t max = SIZE_MAX;
          if (auto v = Param(req, "max")) max = static_cast<size_t>(ParseId(*v, "parameter 'max'"));
          const PackedDetections packed = m.detections->Pack(f, max, m.mission->T0());
          res.set_header("Cache-Control", "no-cache");
          res.set_header("X-SeaMap-Last-Seq", std::to_string(packed.last_seq));
          res.set_header("X-SeaMap-Records", std::to_string(packed.count));
          res.set_content(std::string(packed.bytes.begin(), packed.bytes.end()), "application/octet-stream");
        }));
  s.Get(P + R"(/api/detections/([^/]+))", Guard([resolve, k](const httplib::Request& req, httplib::Response& res) {
          const MissionServices m = resolve(req);
          const int64_t id = ParseId(req.matches[k + 1], "detection id");
          auto d = m.detections->Get(id);
          if (!d) throw ApiError(404, "no detection " + std::to_string(id));
          SendJson(res, *d);
        }));

  auto require_token = [token = options.token](const httplib::Request& req, httplib::Response& res) {
    if (Authorized(req, token)) return true;
    res.set_header("WWW-Authenticate", "Bearer realm=\"seamap\"");
    SendError(res, 401,
              req.has_header("Authorization")
                  ? "wrong token: 'Authorization: Bearer TOKEN' must give the server's --token"
                  : "writing needs 'Authorization: Bearer TOKEN' (the server's --token)");
    return false;
  };
  // The console checks a token as soon as it is entered, before any write.
  s.Get(P + "/api/auth", Guard([require_token](const httplib::Request& req, httplib::Response& res) {
          res.set_header("Cache-Control", "no-store");
          if (require_token(req, res)) res.status = 204;
        }));
  s.Post(P + "/api/detections", Guard([resolve, require_token](const httplib::Request& req, httplib::Response& res) {
           const MissionServices m = resolve(req);
           if (!require_token(req, res)) return;
           nlohmann::json feature = m.detections->Create(ParseBody(req));
           res.set_header("Location", req.path + "/" + std::to_string(feature["id"].get<int64_t>()));
           SendJson(res, feature, 201);
         }));
  s.Patch(P + R"(/api/detections/([^/]+))",
          Guard([resolve, k, require_token](const httplib::Request& req, httplib::Response& res) {
            const MissionServices m = resolve(req);
            if (!require_token(req, res)) return;
            const int64_t id = ParseId(req.matches[k + 1], "detection id");
            SendJson(res, m.detections->Update(id, ParseBody(req)));
          }));
  s.Delete(P + R"(/api/detections/([^/]+))",
           Guard([resolve, k, require_token](const httplib::Request& req, httplib::Response& res) {
             const MissionServices m = resolve(req);
             if (!require_token(req, res)) return;
             m.detections->Delete(ParseId(req.matches[k + 1], "detection id"));
             res.status = 204;
           }));

  s.Get(P + "/api/events",
        [resolve, streams, max_streams = options.max_streams](const httplib::Request& req, httplib::Response& res) {
          // Bad parameters are refused before the stream counts against the cap.
          StreamSettings settings;
          MissionServices m;
          try {
            m = resolve(req);
            settings = ParseStreamSettings(req);
          } catch (const ApiError& e) {
            SendError(res, e.status(), e.what());
            return;
          }
          if (streams->fetch_add(1) >= max_streams) {
            streams->fetch_sub(1);
            res.set_header("Retry-After", "10");
            SendError(res, 503, "too many event streams open (limit " + std::to_string(max_streams) + ")");
            return;
          }
          uint64_t cursor = m.events->LastId();
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
              [hub = m.events, keep = m.keep, position, greeted, gzip, settings](size_t, httplib::DataSink& sink) {
                auto send = [&](const std::string& text) {
                  if (!gzip) return sink.write(text.data(), text.size());
                  const std::string packed = gzip->Write(text);
                  return sink.write(packed.data(), packed.size());
                };
                if (!*greeted) {
                  *greeted = true;
                  return send("retry: 2000\n: seamap events\n\n");
                }
                auto events = hub->WaitAfter(*position, settings.heartbeat);
                if (!events.empty() && settings.batch.count() > 0 && !hub->closed()) {
                  // Gather what comes in the next moments into one write (and one coalesced batch).
                  std::this_thread::sleep_for(settings.batch);
                  events = hub->WaitAfter(*position, std::chrono::milliseconds(0));
                }
                if (!events.empty()) *position = events.back().id;
                std::string out;
                std::vector<Event> kept;
                for (Event& e : events)
                  if (settings.filter.Keep(e)) kept.push_back(std::move(e));
                if (settings.coalesce) kept = Coalesce(std::move(kept));
                for (const Event& e : kept) out += FormatEvent(e);
                if (hub->closed()) {  // shutting down: deliver the last events (e.g. "complete"), then end
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
              [streams](bool) { streams->fetch_sub(1); });
        });
}

}  // namespace seamap::server
