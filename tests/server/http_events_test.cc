// Live events, compression, the console's static files and path safety, binding.
#include "tests/server/http_test_fixture.h"

namespace seamap::server {
namespace {

using namespace http_test;

TEST_F(HttpServerTest, EventsArriveOnTheStreamWithIds) {
  Start();
  EventStream stream(server_->port());
  ASSERT_TRUE(stream.WaitFor(Greeted));
  EXPECT_EQ(stream.status(), 200);
  EXPECT_EQ(stream.header("Content-Type"), "text/event-stream");
  EXPECT_EQ(stream.header("Cache-Control"), "no-cache");

  const std::string version = TileVersionHex(TileVersion(mission_.tiles.at(TileId{3, 4, 2})));
  const json tile = {{"layer", ""}, {"z", 3}, {"x", 4}, {"y", 2}, {"version", version}};
  const uint64_t tile_id = events_.Publish("tile", tile.dump());
  events_.Publish("pose", R"({"frame":4,"lat":43.0,"lon":5.0})");
  ASSERT_TRUE(stream.WaitForEvents(2));
  auto events = stream.Events();
  EXPECT_EQ(events[0].type, "tile");
  EXPECT_EQ(events[0].id, std::to_string(tile_id));
  EXPECT_EQ(json::parse(events[0].data), tile);
  EXPECT_EQ(events[1].type, "pose");
  EXPECT_EQ(events[1].id, std::to_string(tile_id + 1));

  // The event's version is the tile's ETag without quotes.
  EXPECT_EQ(Get("/tiles/3/4/2.png")->get_header_value("ETag"), "\"" + version + "\"");

  // A mark made through the API is announced on the stream.
  auto created = Client()->Post("/api/detections", Mark(5.002, 43.002, "wreck").dump(), "application/json");
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201);
  ASSERT_TRUE(stream.WaitForEvents(3));
  const SseEvent detection = stream.Events()[2];
  EXPECT_EQ(detection.type, "detection");
  EXPECT_EQ(detection.id, std::to_string(tile_id + 2));
  EXPECT_EQ(json::parse(detection.data)["action"], "created");
  EXPECT_EQ(json::parse(detection.data)["id"], 3);
  EXPECT_EQ(json::parse(detection.data)["feature"], json::parse(created->body));
}

TEST_F(HttpServerTest, LastEventIdResumesWhereTheClientLeftOff) {
  Start();
  for (int i = 1; i <= 3; ++i) events_.Publish("track", "{\"seq\":" + std::to_string(i) + "}");

  EventStream resumed(server_->port(), {{"Last-Event-ID", "1"}});
  ASSERT_TRUE(resumed.WaitForEvents(2));
  auto events = resumed.Events();
  EXPECT_EQ(events[0].id, "2");
  EXPECT_EQ(events[1].id, "3");

  EventStream fresh(server_->port());
  ASSERT_TRUE(fresh.WaitFor(Greeted));
  // An id from an earlier server run (beyond ours) is ignored: only new events.
  EventStream stale(server_->port(), {{"Last-Event-ID", "9999"}});
  ASSERT_TRUE(stale.WaitFor(Greeted));
  events_.Publish("track", "{\"seq\":4}");
  ASSERT_TRUE(resumed.WaitForEvents(3));
  ASSERT_TRUE(fresh.WaitForEvents(1));
  ASSERT_TRUE(stale.WaitForEvents(1));
  EXPECT_EQ(resumed.Events()[2].id, "4");
  for (EventStream* s : {&fresh, &stale}) {
    auto got = s->Events();
    ASSERT_EQ(got.size(), 1u) << "no replay of old events without Last-Event-ID";
    EXPECT_EQ(got[0].id, "4");
  }
}

TEST_F(HttpServerTest, StreamsBeyondTheCapAre503) {
  ServerOptions o = Options();
  o.max_streams = 1;
  Start(o);
  EventStream first(server_->port());
  ASSERT_TRUE(first.WaitFor(Greeted));
  ExpectError(Get("/api/events"), 503, "too many", "second stream");
  EXPECT_EQ(Get("/api/events")->get_header_value("Retry-After"), "10");
  // Tiles and the API still answer while the stream is open.
  EXPECT_EQ(Get("/tiles/3/4/2.png")->status, 200);
  EXPECT_EQ(Get("/api/status")->status, 200);

  // Once the first stream is gone (noticed at its next write), a new one is let in.
  first.Close();
  bool admitted = false;
  for (int i = 0; i < 200 && !admitted; ++i) {
    events_.Publish("progress", "{}");
    auto res = Get("/api/status");  // a request in between: the closed stream's write fails meanwhile
    EventStream next(server_->port());
    admitted = next.WaitFor([](const std::string& t) { return Greeted(t); });
    if (!admitted) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(admitted);
}

TEST_F(HttpServerTest, StreamsAtTheCapDoNotStarveOtherRequests) {
  ServerOptions o = Options();
  o.threads = 2;
  o.max_streams = 2;
  Start(o);
  EventStream a(server_->port()), b(server_->port());
  ASSERT_TRUE(a.WaitFor(Greeted));
  ASSERT_TRUE(b.WaitFor(Greeted));
  for (int i = 0; i < 10; ++i) {
    auto res = Get(i % 2 ? "/tiles/3/4/2.png" : "/api/status");
    ASSERT_TRUE(res) << i;
    EXPECT_EQ(res->status, 200) << i;
  }
  EXPECT_EQ(Get("/api/events")->status, 503);
}

TEST_F(HttpServerTest, StoppingTheServerDeliversTheLastEventsAndEndsStreams) {
  Start();
  EventStream stream(server_->port());
  ASSERT_TRUE(stream.WaitFor(Greeted));
  events_.Publish("progress", R"({"state":"complete"})");
  server_->Stop();
  EXPECT_TRUE(stream.WaitForEnd());
  auto events = stream.Events();
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.back().type, "progress");
}

// --- compression, console, unknown paths --------------------------------------------

TEST_F(HttpServerTest, JsonIsGzippedForClientsThatAcceptIt) {
  Start();
  auto raw = Client();
  raw->set_decompress(false);
  for (const std::string path : {"/api/detections", "/api/status", "/tiles.json", "/api/track"}) {
    auto res = raw->Get(path.c_str(), {{"Accept-Encoding", "gzip"}});
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 200) << path;
    EXPECT_EQ(res->get_header_value("Content-Encoding"), "gzip") << path;
    ASSERT_GE(res->body.size(), 2u);
    EXPECT_EQ(static_cast<unsigned char>(res->body[0]), 0x1f) << path;
    EXPECT_EQ(static_cast<unsigned char>(res->body[1]), 0x8b) << path;
  }
  // Decompressed, it is the same JSON.
  auto client = Client();
  auto res = client->Get("/api/detections", {{"Accept-Encoding", "gzip"}});
  ASSERT_TRUE(res);
  EXPECT_EQ(FeatureIds(json::parse(res->body)), (std::vector<int64_t>{1, 2}));

  // Without Accept-Encoding: plain.
  auto plain = raw->Get("/api/status");
  ASSERT_TRUE(plain);
  EXPECT_FALSE(plain->has_header("Content-Encoding"));
  EXPECT_TRUE(json::parse(plain->body).is_object());

  // Tiles are compressed images already: sent as they are.
  auto tile = raw->Get("/tiles/3/4/2.png", {{"Accept-Encoding", "gzip"}});
  ASSERT_TRUE(tile);
  EXPECT_FALSE(tile->has_header("Content-Encoding"));
  EXPECT_EQ(tile->body, Text(mission_.tiles.at(TileId{3, 4, 2})));
}

TEST_F(HttpServerTest, TheEventStreamIsGzippedAndFlushedEventByEvent) {
  Start();
  // Each write is flushed (Z_SYNC_FLUSH): an event is readable as soon as it is sent.
  EventStream stream(server_->port(), {{"Accept-Encoding", "gzip, deflate"}});
  ASSERT_TRUE(stream.WaitFor(Greeted));
  EXPECT_EQ(stream.header("Content-Encoding"), "gzip");
  events_.Publish("tile", "{}");
  ASSERT_TRUE(stream.WaitForEvents(1));
  events_.Publish("pose", R"({"frame":1})");
  ASSERT_TRUE(stream.WaitForEvents(2));
  EXPECT_EQ(stream.Events()[1].data, R"({"frame":1})");

  EventStream plain(server_->port(), {{"Accept-Encoding", "gzip;q=0, identity"}});
  ASSERT_TRUE(plain.WaitFor(Greeted));
  EXPECT_EQ(plain.header("Content-Encoding"), "");
}

// A console on a weak link asks only for what it shows: the layers, zoom
// levels and area in view, batched, superseded updates dropped.
TEST_F(HttpServerTest, AStreamCarriesOnlyTheLayersZoomsAndAreaAsked) {
  Start();
  auto tile = [](const std::string& layer, int z, int x, int y, const std::string& version) {
    return json{{"layer", layer}, {"z", z}, {"x", x}, {"y", y}, {"version", version}}.dump();
  };
  // 3/4/2 lies at lon 0..45, lat 40.98..66.51; 3/0/0 far from it.
  const std::string query = "/api/events?layers=,enhanced&zoom=3-4&bbox=10,45,20,50&types=tile,pose";
  EventStream filtered(server_->port(), {}, query);
  ASSERT_TRUE(filtered.WaitFor(Greeted));
  EXPECT_EQ(filtered.status(), 200);
  events_.Publish("tile", tile("", 3, 4, 2, "a"));          // kept
  events_.Publish("tile", tile("other", 3, 4, 2, "b"));     // another layer
  events_.Publish("tile", tile("", 5, 16, 8, "c"));         // another zoom
  events_.Publish("tile", tile("", 3, 0, 0, "d"));          // out of the area
  events_.Publish("track", R"({"seq":1})");                 // not asked for
  events_.Publish("tile", tile("enhanced", 4, 8, 5, "e"));  // kept
  events_.Publish("pose", R"({"frame":2})");                // kept
  ASSERT_TRUE(filtered.WaitForEvents(3));
  auto got = filtered.Events();
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(json::parse(got[0].data)["version"], "a");
  EXPECT_EQ(json::parse(got[1].data)["version"], "e");
  EXPECT_EQ(got[2].type, "pose");
  EXPECT_EQ(got[2].id, std::to_string(events_.LastId()));

  // A new stream with other filters goes on after the last id it saw.
  EventStream next(server_->port(), {}, "/api/events?types=track&after=" + got[0].id);
  ASSERT_TRUE(next.WaitForEvents(1));
  EXPECT_EQ(next.Events()[0].data, R"({"seq":1})");
  // The browser's reconnect of that stream sends Last-Event-ID (later than
  // after=): it goes on from there, nothing is delivered twice.
  EventStream reconnected(server_->port(), {{"Last-Event-ID", std::to_string(events_.LastId())}},
                          "/api/events?types=track,pose&after=" + got[0].id);
  ASSERT_TRUE(reconnected.WaitFor(Greeted));
  events_.Publish("track", R"({"seq":2})");
  ASSERT_TRUE(reconnected.WaitForEvents(1));
  EXPECT_EQ(reconnected.Events()[0].data, R"({"seq":2})");

  for (const auto& [q, needle] : std::vector<std::pair<std::string, std::string>>{{"types=tile,nope", "types"},
                                                                                  {"zoom=3-x", "zoom"},
                                                                                  {"zoom=9-3", "zoom"},
                                                                                  {"bbox=1,2,3", "bbox"},
                                                                                  {"bbox=20,0,10,5", "bbox"},
                                                                                  {"batch_ms=99999", "batch_ms"},
                                                                                  {"heartbeat_s=0", "heartbeat_s"}})
    ExpectError(Get("/api/events?" + q), 400, needle, q);
}

TEST_F(HttpServerTest, ABatchedStreamSendsTheLastOfRepeatedUpdates) {
  Start();
  const auto tile = [](const std::string& version) {
    return json{{"layer", ""}, {"z", 3}, {"x", 4}, {"y", 2}, {"version", version}}.dump();
  };
  const uint64_t before = events_.LastId();
  events_.Publish("tile", tile("v1"));
  events_.Publish("pose", R"({"frame":1})");
  events_.Publish("track", R"({"seq":1})");
  events_.Publish("tile", tile("v2"));
  events_.Publish("pose", R"({"frame":2})");
  events_.Publish("track", R"({"seq":2})");
  // Resuming from before them: all six come in one batch, superseded ones dropped.
  EventStream batched(server_->port(), {}, "/api/events?batch_ms=300&after=" + std::to_string(before));
  ASSERT_TRUE(batched.WaitForEvents(4));
  std::vector<std::string> got;
  for (const auto& e : batched.Events()) got.push_back(e.type + " " + e.data);
  EXPECT_EQ(got, (std::vector<std::string>{"track {\"seq\":1}", "tile " + tile("v2"), "pose {\"frame\":2}",
                                           "track {\"seq\":2}"}));
}

TEST_F(HttpServerTest, AHeartbeatStreamSendsPingsTheBrowserSees) {
  Start();
  EventStream stream(server_->port(), {}, "/api/events?heartbeat_s=1");
  ASSERT_TRUE(stream.WaitForEvents(1));
  const auto ping = stream.Events()[0];
  EXPECT_EQ(ping.type, "ping");
  EXPECT_EQ(ping.id, "") << "a ping must not move the browser's Last-Event-ID";
  EXPECT_EQ(json::parse(ping.data)["last_id"], events_.LastId());
}

TEST_F(HttpServerTest, TheConsoleIsServedFromTheWebDir) {
  Start();
  auto index = Get("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->status, 200);
  EXPECT_EQ(index->body, ReadAll(web_ / "index.html"));
  EXPECT_NE(index->get_header_value("Content-Type").find("text/html"), std::string::npos);
  auto index2 = Get("/index.html");
  ASSERT_TRUE(index2);
  EXPECT_EQ(index2->body, index->body);

  auto js = Get("/js/app.js");
  ASSERT_TRUE(js);
  EXPECT_EQ(js->status, 200);
  EXPECT_EQ(js->body, "console.log('seamap');");
  EXPECT_EQ(js->get_header_value("Content-Type"), "text/javascript");

  ExpectError(Get("/nothing-here.html"), 404, "not found", "unknown file");
}

TEST_F(HttpServerTest, NoPathEscapesTheWebDir) {
  Start();
  // Sent byte for byte, as an attacker would; the secret sits next to the web dir.
  for (const std::string target :
       {"/../secret.txt", "/js/../../secret.txt", "/%2e%2e/secret.txt", "/%2E%2E/secret.txt",
        "/js/%2e%2e/%2e%2e/secret.txt", "/..%2fsecret.txt", "/%2e%2e%2fsecret.txt", "/js/..%2f..%2fsecret.txt",
        "/..\\secret.txt", "/%2e%2e%5csecret.txt", "//../secret.txt", "/./../secret.txt", "/js/./../../secret.txt"}) {
    RawResponse res = RawGet(server_->port(), target);
    EXPECT_EQ(res.text.find("TOP SECRET"), std::string::npos) << target;
    EXPECT_GE(res.status, 400) << target << "\n" << res.text.substr(0, 200);
    EXPECT_LT(res.status, 500) << target;
  }
  // A ".." that stays inside is harmless.
  RawResponse inside = RawGet(server_->port(), "/js/../index.html");
  EXPECT_EQ(inside.text.find("TOP SECRET"), std::string::npos);
}

TEST_F(HttpServerTest, UnknownApiPathsAre404Json) {
  Start();
  ExpectError(Get("/api/nope"), 404, "/api/nope", "unknown endpoint");
  ExpectError(Get("/api/frames/1/nope"), 404, "no such API endpoint", "unknown frame sub-path");
  ExpectError(Get("/api/"), 404, "no such API endpoint", "bare /api/");
  ExpectError(Client()->Post("/api/nope", "{}", "application/json"), 404, "", "POST to an unknown endpoint");
  ExpectError(Client()->Post("/api/status", "{}", "application/json"), 404, "", "POST to a GET endpoint");
}

TEST_F(HttpServerTest, WithoutAWebDirOnlyTheApiIsServed) {
  ServerOptions o = Options();
  o.web_dir.clear();
  Start(o);
  ExpectError(Get("/"), 404, "not found", "no console");
  EXPECT_EQ(Get("/api/status")->status, 200);
}

TEST_F(HttpServerTest, BindingATakenPortNamesTheOption) {
  Start();
  ServerOptions o = Options();
  o.port = server_->port();
  EventHub events;
  HttpServer second(o, tiles_.get(), &state_, registry_.get(), &events);
  try {
    second.Bind();
    FAIL() << "bound a port already in use";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--port");
  }
}

}  // namespace
}  // namespace seamap::server
