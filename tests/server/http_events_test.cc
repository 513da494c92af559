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

TEST_F(HttpServerTest, TheEventStreamIsNeverCompressed) {
  Start();
  // Browsers always send Accept-Encoding; a compressed stream would sit in the compressor's buffer.
  EventStream stream(server_->port(), {{"Accept-Encoding", "gzip, deflate"}});
  ASSERT_TRUE(stream.WaitFor(Greeted));
  EXPECT_EQ(stream.header("Content-Encoding"), "");
  events_.Publish("tile", "{}");
  EXPECT_TRUE(stream.WaitForEvents(1));
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
