// The HTTP API over a real socket: a real MBTiles mission, a real HttpServer on
// loopback and httplib::Client (or a raw socket where the client would tidy
// the request up). See server/README.md for the contract.
#include "server/http_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <fstream>
#include <functional>
#include <iterator>
#include <thread>

#include <httplib.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "core/tiles/folder_store.h"
#include "core/util/error.h"
#include "tests/server/test_mission.h"
#include "tests/testing/temp_dir.h"

namespace seamap::server {
namespace {

using nlohmann::json;
using test::QuotedVersion;
using test::Text;

constexpr auto kPatience = std::chrono::seconds(30);  // generous: never a timing assertion

std::string ReadAll(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<int64_t> FeatureIds(const json& collection) {
  std::vector<int64_t> ids;
  for (const auto& f : collection.at("features")) ids.push_back(f.at("id").get<int64_t>());
  return ids;
}

std::vector<int> FrameIds(const json& answer) {
  std::vector<int> ids;
  for (const auto& f : answer.at("frames")) ids.push_back(f.at("id").get<int>());
  return ids;
}

// A response as it came off the wire: status code and the raw text.
struct RawResponse {
  int status = 0;
  std::string text;
};

// Sends the request line exactly as given (no normalisation, no encoding).
RawResponse RawGet(int port, const std::string& target) {
  RawResponse out;
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return out;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  ::inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  timeval timeout{30, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    const std::string request = "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
    if (::send(fd, request.data(), request.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(request.size())) {
      char buf[4096];
      ssize_t n;
      while ((n = ::recv(fd, buf, sizeof buf, 0)) > 0) out.text.append(buf, static_cast<size_t>(n));
    }
  }
  ::close(fd);
  if (out.text.rfind("HTTP/1.1 ", 0) == 0) out.status = std::atoi(out.text.c_str() + 9);
  return out;
}

struct SseEvent {
  std::string id, type, data;
};

// Parses "id: N\nevent: T\ndata: D\n\n" blocks; comments and retry lines are skipped.
std::vector<SseEvent> ParseEvents(const std::string& text) {
  std::vector<SseEvent> out;
  size_t start = 0;
  while (true) {
    const size_t end = text.find("\n\n", start);
    if (end == std::string::npos) break;
    SseEvent e;
    std::stringstream block(text.substr(start, end - start));
    std::string line;
    while (std::getline(block, line)) {
      if (line.rfind("id: ", 0) == 0) e.id = line.substr(4);
      if (line.rfind("event: ", 0) == 0) e.type = line.substr(7);
      if (line.rfind("data: ", 0) == 0) e.data = line.substr(6);
    }
    if (!e.type.empty()) out.push_back(e);
    start = end + 2;
  }
  return out;
}

// An open GET /api/events in a thread of its own, collecting what arrives.
class EventStream {
 public:
  EventStream(int port, httplib::Headers headers = {}) : client_("127.0.0.1", port) {
    client_.set_read_timeout(120);
    for (const auto& [k, v] : headers) headers_sent_.emplace(k, v);
    thread_ = std::thread([this] {
      auto res = client_.Get(
          "/api/events", headers_sent_,
          [this](const httplib::Response& r) {
            std::lock_guard<std::mutex> lock(mutex_);
            status_ = r.status;
            headers_ = r.headers;
            changed_.notify_all();
            return true;
          },
          [this](const char* data, size_t n) {
            std::lock_guard<std::mutex> lock(mutex_);
            data_.append(data, n);
            changed_.notify_all();
            return !stop_;
          });
      std::lock_guard<std::mutex> lock(mutex_);
      ended_ = true;
      changed_.notify_all();
    });
  }
  ~EventStream() { Close(); }

  void Close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    client_.stop();
    if (thread_.joinable()) thread_.join();
  }
  // Waits (generously) until the received text satisfies `done`.
  bool WaitFor(const std::function<bool(const std::string&)>& done) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, kPatience, [&] { return done(data_) || ended_; }) && done(data_);
  }
  bool WaitForEvents(size_t n) {
    return WaitFor([n](const std::string& text) { return ParseEvents(text).size() >= n; });
  }
  bool WaitForEnd() {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, kPatience, [&] { return ended_; });
  }
  std::vector<SseEvent> Events() {
    std::lock_guard<std::mutex> lock(mutex_);
    return ParseEvents(data_);
  }
  int status() {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
  }
  std::string header(const std::string& name) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = headers_.find(name);
    return it == headers_.end() ? "" : it->second;
  }

 private:
  httplib::Client client_;
  httplib::Headers headers_sent_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::string data_;
  int status_ = 0;
  httplib::Headers headers_;
  bool stop_ = false, ended_ = false;
};

bool Greeted(const std::string& text) { return text.find(": seamap events") != std::string::npos; }

class HttpServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    seamap::testing::WriteFile(web_ / "index.html", "<!doctype html><title>SeaMap console</title>");
    seamap::testing::WriteFile(web_ / "js" / "app.js", "console.log('seamap');");
    seamap::testing::WriteFile(dir_ / "secret.txt", "TOP SECRET");
  }
  void TearDown() override {
    if (server_) server_->Stop();
  }

  ServerOptions Options() const {
    ServerOptions o;
    o.host = "127.0.0.1";
    o.port = 0;
    o.web_dir = web_.string();
    o.threads = 8;
    o.max_streams = 4;
    return o;
  }
  // Serves the test mission as `seamap serve` does; `writable` false: a read-only mission.
  void Start(ServerOptions options, bool writable = true) {
    tiles_ = std::make_unique<TileSource>(mission_.path.string(), readers_);
    writer_ = std::make_unique<MBTilesStore>(mission_.path.string(), writable ? MBTilesStore::Mode::kCreate
                                                                              : MBTilesStore::Mode::kReadOnly);
    state_.Load(*writer_);
    state_.SetLayers(tiles_->Layers(), tiles_->Format());
    registry_ = std::make_unique<DetectionRegistry>(writable ? writer_.get() : nullptr, &events_);
    registry_->Load(*writer_);
    server_ = std::make_unique<HttpServer>(options, tiles_.get(), &state_, registry_.get(), &events_);
    server_->Bind();
    server_->Start();
    ASSERT_GT(server_->port(), 0);
  }
  void Start() { Start(Options()); }

  std::unique_ptr<httplib::Client> Client() const {
    auto c = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    c->set_read_timeout(60);
    c->set_connection_timeout(30);
    return c;
  }
  httplib::Result Get(const std::string& path, const httplib::Headers& headers = {}) {
    return Client()->Get(path.c_str(), headers);
  }
  json GetJson(const std::string& path, int expected_status = 200) {
    auto res = Get(path);
    EXPECT_TRUE(res) << path;
    if (!res) return nullptr;
    EXPECT_EQ(res->status, expected_status) << path << ": " << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json") << path;
    try {
      return json::parse(res->body);
    } catch (const json::exception& e) {
      ADD_FAILURE() << path << ": not JSON: " << res->body;
      return nullptr;
    }
  }
  // The answer must be a JSON error whose message contains `needle`.
  void ExpectError(const httplib::Result& res, int status, const std::string& needle, const std::string& what) {
    ASSERT_TRUE(res) << what;
    EXPECT_EQ(res->status, status) << what << ": " << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json") << what;
    json body = json::parse(res->body, nullptr, false);
    ASSERT_TRUE(body.is_object()) << what << ": " << res->body;
    ASSERT_TRUE(body.contains("error") && body["error"].is_string()) << what << ": " << res->body;
    EXPECT_NE(body["error"].get<std::string>().find(needle), std::string::npos)
        << what << ": " << body["error"].get<std::string>();
  }
  // Detections as a fresh reader of the MBTiles file sees them.
  std::map<int64_t, Detection> StoredDetections() const {
    MBTilesStore reader(mission_.path.string(), MBTilesStore::Mode::kReadOnly);
    std::map<int64_t, Detection> out;
    for (const auto& d : reader.Detections()) out[d.id] = d;
    return out;
  }
  static json Mark(double lon, double lat, const std::string& cls) {
    return {{"type", "Feature"},
            {"geometry", {{"type", "Point"}, {"coordinates", {lon, lat}}}},
            {"properties", {{"class", cls}}}};
  }

  int readers_ = 2;
  seamap::testing::TempDir dir_;
  test::TestMission mission_ = test::WriteTestMission(dir_.path());
  std::filesystem::path web_ = dir_ / "web";
  EventHub events_;
  MissionState state_;
  std::unique_ptr<TileSource> tiles_;
  std::unique_ptr<MBTilesStore> writer_;
  std::unique_ptr<DetectionRegistry> registry_;
  std::unique_ptr<HttpServer> server_;  // last: stopped and destroyed first
};

// --- tiles -------------------------------------------------------------------

TEST_F(HttpServerTest, TilesAreServedWithTheirTypeAndAStrongEtagOfTheirBytes) {
  Start();
  for (const auto& [id, bytes] : mission_.tiles) {
    const std::string path =
        "/tiles/" + std::to_string(id.z) + "/" + std::to_string(id.x) + "/" + std::to_string(id.y) + ".png";
    auto res = Get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 200) << path;
    EXPECT_EQ(res->get_header_value("Content-Type"), "image/png");
    EXPECT_EQ(res->get_header_value("ETag"), QuotedVersion(bytes)) << path;
    EXPECT_EQ(res->body, Text(bytes)) << path;
    EXPECT_EQ(res->get_header_value("Cache-Control"), "public, max-age=300") << "a complete mission";
    EXPECT_EQ(res->get_header_value("Access-Control-Allow-Origin"), "*");
  }
}

TEST_F(HttpServerTest, IfNoneMatchWithTheTilesEtagIsAnswered304) {
  Start();
  const std::string etag = QuotedVersion(mission_.tiles.at(TileId{3, 4, 2}));
  for (const std::string& header : {etag, "\"0000000000000000\", " + etag, "W/" + etag, std::string("*")}) {
    auto res = Get("/tiles/3/4/2.png", {{"If-None-Match", header}});
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 304) << header;
    EXPECT_TRUE(res->body.empty()) << header;
    EXPECT_EQ(res->get_header_value("ETag"), etag);
  }
  auto other = Get("/tiles/3/4/2.png", {{"If-None-Match", "\"0000000000000000\""}});
  ASSERT_TRUE(other);
  EXPECT_EQ(other->status, 200);
  EXPECT_EQ(other->body, Text(mission_.tiles.at(TileId{3, 4, 2})));
}

TEST_F(HttpServerTest, ARewrittenTileGetsANewEtagOnceInvalidated) {
  Start();
  const std::string old_etag = QuotedVersion(mission_.tiles.at(TileId{3, 4, 2}));
  ASSERT_EQ(Get("/tiles/3/4/2.png")->get_header_value("ETag"), old_etag);
  const auto replaced = test::Png(16, 16, 250);
  writer_->PutTile(TileId{3, 4, 2}, replaced);
  writer_->Flush();
  tiles_->Invalidate("", TileId{3, 4, 2});  // what the replay does after committing a tile
  auto res = Get("/tiles/3/4/2.png", {{"If-None-Match", old_etag}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200) << "the browser's copy is stale";
  EXPECT_EQ(res->get_header_value("ETag"), QuotedVersion(replaced));
  EXPECT_EQ(res->body, Text(replaced));
}

TEST_F(HttpServerTest, TilesOfAGrowingMapMustBeRevalidated) {
  Start();
  Progress p = state_.progress();
  p.state = "building";
  state_.SetProgress(p);
  auto res = Get("/tiles/3/4/2.png");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->get_header_value("Cache-Control"), "no-cache");
  auto missing = Get("/tiles/3/7/7.png");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 204);
  EXPECT_EQ(missing->get_header_value("Cache-Control"), "no-cache") << "the tile may appear later";
}

TEST_F(HttpServerTest, AMissingTileIs204WithoutBody) {
  Start();
  for (const std::string path : {"/tiles/3/7/7.png", "/tiles/0/0/0.png", "/tiles/30/0/0.png"}) {
    auto res = Get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 204) << path;
    EXPECT_TRUE(res->body.empty()) << path;
    EXPECT_FALSE(res->has_header("ETag")) << path;
  }
}

TEST_F(HttpServerTest, MalformedOrOutOfRangeTilePathsAre400WithAJsonError) {
  Start();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"/tiles/31/0/0.png", "zoom"},        {"/tiles/3/8/0.png", "2^z"},
      {"/tiles/3/0/8.png", "2^z"},          {"/tiles/a/0/0.png", "non-negative integers"},
      {"/tiles/3/-1/2.png", "non-negative"}, {"/tiles/3/4/2", "{y}.{ext}"},
      {"/tiles/3/4.png", "tile path"},      {"/tiles/enhanced/3/4/5/6.png", "tile path"},
      {"/tiles/3/4/.png", "tile path"},     {"/tiles/99999999999/0/0.png", "tile path"},
      {"/tiles/", "tile path"},             {"/tiles/3/4/2.png/", "tile path"}};
  for (const auto& [path, needle] : cases) ExpectError(Get(path), 400, needle, path);
}

TEST_F(HttpServerTest, AnotherExtensionThanTheMissionsFormatIs404) {
  Start();
  ExpectError(Get("/tiles/3/4/2.jpg"), 404, ".png", "jpg");
  ExpectError(Get("/tiles/3/4/2.webp"), 404, ".png", "webp");
  ExpectError(Get("/tiles/enhanced/3/4/2.jpeg"), 404, ".png", "layer jpeg");
}

TEST_F(HttpServerTest, LayerTilesAreServedUnderTheLayerName) {
  Start();
  const auto& bytes = mission_.enhanced.at(TileId{3, 4, 2});
  auto res = Get("/tiles/enhanced/3/4/2.png");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(res->body, Text(bytes));
  EXPECT_EQ(res->get_header_value("ETag"), QuotedVersion(bytes));
  EXPECT_NE(res->body, Text(mission_.tiles.at(TileId{3, 4, 2})));

  auto revalidated = Get("/tiles/enhanced/3/4/2.png", {{"If-None-Match", QuotedVersion(bytes)}});
  ASSERT_TRUE(revalidated);
  EXPECT_EQ(revalidated->status, 304);

  auto missing = Get("/tiles/enhanced/3/4/3.png");
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 204) << "the main map has 3/4/3, the layer does not";

  ExpectError(Get("/tiles/nope/3/4/2.png"), 404, "nope", "unknown layer");
  ExpectError(Get("/tiles/raw/3/4/2.png"), 404, "raw", "the main map is not a layer");
}

TEST_F(HttpServerTest, TileJsonDescribesTheMission) {
  Start();
  const std::string base = "http://127.0.0.1:" + std::to_string(server_->port());
  const json tj = GetJson("/tiles.json");
  EXPECT_EQ(tj["tilejson"], "3.0.0");
  EXPECT_EQ(tj["tiles"], json::array({base + "/tiles/{z}/{x}/{y}.png"}));
  EXPECT_EQ(tj["bounds"], json::array({4.999, 42.999, 5.011, 43.011}));
  EXPECT_EQ(tj["center"], json::array({5.005, 43.005, 17}));
  EXPECT_EQ(tj["minzoom"], 15);
  EXPECT_EQ(tj["maxzoom"], 19);
  EXPECT_EQ(tj["attribution"], "Test survey");
  EXPECT_EQ(tj["name"], "Test mission");
  EXPECT_EQ(tj["format"], "png");
  EXPECT_EQ(tj["seamap_layers"], json::array({"raw", "enhanced"}));
  for (const auto& [key, value] : tj.items())
    EXPECT_NE(key.rfind("layer.", 0), 0u) << "another layer's key leaked into the main TileJSON: " << key;

  // The template follows the Host the client used (a phone on the boat's Wi-Fi).
  auto res = Get("/tiles.json", {{"Host", "seamap.local:9000"}});
  ASSERT_TRUE(res);
  EXPECT_EQ(json::parse(res->body)["tiles"][0], "http://seamap.local:9000/tiles/{z}/{x}/{y}.png");

  // A TileJSON's template must actually serve the tiles.
  const std::string tile = json::parse(Get("/tiles.json")->body)["tiles"][0].get<std::string>();
  std::string path = tile.substr(base.size());
  path.replace(path.find("{z}/{x}/{y}"), 11, "3/4/2");
  EXPECT_EQ(Get(path)->body, Text(mission_.tiles.at(TileId{3, 4, 2})));
}

TEST_F(HttpServerTest, LayerTileJson) {
  Start();
  const json tj = GetJson("/tiles/enhanced.json");
  EXPECT_EQ(tj["tilejson"], "3.0.0");
  EXPECT_EQ(tj["tiles"][0],
            "http://127.0.0.1:" + std::to_string(server_->port()) + "/tiles/enhanced/{z}/{x}/{y}.png");
  EXPECT_EQ(tj["name"], "Test mission (enhanced)");
  EXPECT_EQ(tj["bounds"], json::array({4.999, 42.999, 5.011, 43.011}));
  EXPECT_EQ(tj["minzoom"], 15);
  EXPECT_EQ(tj["maxzoom"], 19);
  EXPECT_TRUE(tj.contains("attribution"));
  ExpectError(Get("/tiles/nope.json"), 404, "nope", "unknown layer");
}

TEST_F(HttpServerTest, AVersionQueryStillServesTheTile) {
  Start();
  // The console may ask for the version a `tile` event named, to get past caches.
  const auto& bytes = mission_.tiles.at(TileId{3, 4, 2});
  auto res = Get("/tiles/3/4/2.png?v=" + TileVersionHex(TileVersion(bytes)));
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->body, Text(bytes));
}

// Layer requests from many connections through one reader, starting with a
// stale metadata snapshot (TileSourceTest.ALayerRequestWithOneReader... pins
// down the deadlock this once had; here the whole path must still answer).
TEST_F(HttpServerTest, ParallelLayerRequestsThroughOneReaderAllAnswer) {
  readers_ = 1;
  Start();
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));  // the metadata snapshot is now stale
  std::atomic<int> ok{0}, failed{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 6; ++t) {
    threads.emplace_back([&, t] {
      auto client = Client();
      for (int i = 0; i < 5; ++i) {
        const std::string path = (t + i) % 2 ? "/tiles/enhanced/3/4/2.png" : "/tiles/enhanced/3/4/3.png";
        auto res = client->Get(path.c_str());
        (res && (res->status == 200 || res->status == 204) ? ok : failed)++;
      }
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(ok.load(), 30);
  EXPECT_EQ(failed.load(), 0);
}

TEST(HttpServerFolderTest, AJpegFolderMissionServesJpgAndJpeg) {
  seamap::testing::TempDir dir;
  const auto folder = dir / "pyramid";
  std::vector<uint8_t> jpg;
  cv::imencode(".jpg", cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3)), jpg);
  {
    FolderStore store(folder.string(), "jpg");
    store.PutTile(TileId{4, 3, 2}, jpg);
    store.SetMetadata("name", "Folder mission");
    store.SetMetadata("format", "jpg");
    store.Flush();
  }
  EventHub events;
  TileSource tiles(folder.string(), 1);
  FolderStore records(folder.string(), "jpg", FolderStore::Mode::kReadOnly);
  MissionState state;
  state.Load(records);
  state.SetLayers(tiles.Layers(), tiles.Format());
  DetectionRegistry registry(nullptr, &events);
  ServerOptions o;
  o.host = "127.0.0.1";
  o.port = 0;
  o.threads = 4;
  HttpServer server(o, &tiles, &state, &registry, &events);
  server.Bind();
  server.Start();
  httplib::Client client("127.0.0.1", server.port());
  client.set_read_timeout(60);
  for (const char* path : {"/tiles/4/3/2.jpg", "/tiles/4/3/2.jpeg"}) {
    auto res = client.Get(path);
    ASSERT_TRUE(res) << path;
    EXPECT_EQ(res->status, 200) << path;
    EXPECT_EQ(res->get_header_value("Content-Type"), "image/jpeg") << path;
    EXPECT_EQ(res->get_header_value("ETag"), QuotedVersion(jpg)) << path;
    EXPECT_EQ(res->body, Text(jpg)) << path;
  }
  auto png = client.Get("/tiles/4/3/2.png");
  ASSERT_TRUE(png);
  EXPECT_EQ(png->status, 404);
  auto tj = client.Get("/tiles.json");
  ASSERT_TRUE(tj);
  EXPECT_EQ(json::parse(tj->body)["tiles"][0],
            "http://127.0.0.1:" + std::to_string(server.port()) + "/tiles/{z}/{x}/{y}.jpg");
  EXPECT_EQ(json::parse(tj->body)["name"], "Folder mission");
  server.Stop();
}

// --- mission -------------------------------------------------------------------

TEST_F(HttpServerTest, StatusReportsTheMission) {
  Start();
  events_.Publish("progress", "{}");
  const json s = GetJson("/api/status");
  EXPECT_EQ(s["name"], "Test mission");
  EXPECT_EQ(s["state"], "complete");
  EXPECT_EQ(s["replay"], false);
  EXPECT_EQ(s["frames_done"], 4);
  EXPECT_EQ(s["frames_total"], 4);
  EXPECT_EQ(s["frames_rejected"], 1);
  EXPECT_TRUE(s["tiles_written"].is_number());
  EXPECT_TRUE(s["frames_per_s"].is_number());
  EXPECT_DOUBLE_EQ(s["progress"].get<double>(), 1.0);
  EXPECT_EQ(s["origin"], json::array({43.0, 5.0}));
  EXPECT_EQ(s["layers"], json::array({"raw", "enhanced"}));
  EXPECT_EQ(s["format"], "png");
  EXPECT_EQ(s["token_required"], false);
  EXPECT_EQ(s["writable"], true);
  EXPECT_EQ(s["event_seq"], 1);
  const json pose = s["last_pose"];
  ASSERT_TRUE(pose.is_object());
  EXPECT_EQ(pose["frame"], 3);
  for (const char* key : {"lat", "lon", "heading_deg", "depth_m", "altitude_m", "time_s"})
    EXPECT_TRUE(pose[key].is_number()) << key;
  EXPECT_EQ(Get("/api/status")->get_header_value("Cache-Control"), "no-cache");
}

TEST_F(HttpServerTest, StatusOfAProtectedReadOnlyMission) {
  ServerOptions o = Options();
  o.token = "s3cret";
  Start(o, /*writable=*/false);
  const json s = GetJson("/api/status");
  EXPECT_EQ(s["token_required"], true);
  EXPECT_EQ(s["writable"], false);
  EXPECT_EQ(s.dump().find("s3cret"), std::string::npos) << "the token is never shown";
}

TEST_F(HttpServerTest, TrackIsALineStringAndSinceJoinsTheNewPiece) {
  Start();
  const json all = GetJson("/api/track");
  EXPECT_EQ(all["type"], "Feature");
  EXPECT_EQ(all["geometry"]["type"], "LineString");
  ASSERT_EQ(all["geometry"]["coordinates"].size(), 5u);
  EXPECT_NEAR(all["geometry"]["coordinates"][1][0].get<double>(), 5.00005, 1e-9);  // [lon, lat]
  EXPECT_NEAR(all["geometry"]["coordinates"][1][1].get<double>(), 43.00005, 1e-9);
  EXPECT_EQ(all["properties"]["from"], 0);
  EXPECT_EQ(all["properties"]["next"], 5);
  EXPECT_EQ(all["properties"]["times"], json::array({0.0, 2.0, 4.0, 6.0, 8.0}));

  // The client has points 0..2 (asked next=3): it gets 2 again, then 3 and 4.
  const json since3 = GetJson("/api/track?since=3");
  EXPECT_EQ(since3["properties"]["from"], 2);
  EXPECT_EQ(since3["properties"]["next"], 5);
  ASSERT_EQ(since3["geometry"]["coordinates"].size(), 3u);
  EXPECT_NEAR(since3["geometry"]["coordinates"][0][1].get<double>(), 43.0001, 1e-9);

  // Up to date: a single point is no line.
  const json since5 = GetJson("/api/track?since=5");
  EXPECT_TRUE(since5["geometry"].is_null());
  EXPECT_EQ(since5["properties"]["from"], 4);
  EXPECT_EQ(since5["properties"]["next"], 5);

  const json later = GetJson("/api/track?since=50");
  EXPECT_TRUE(later["geometry"].is_null());
  EXPECT_EQ(later["properties"]["next"], 5);
  EXPECT_TRUE(later["properties"]["times"].empty());

  ExpectError(Get("/api/track?since=-1"), 400, "since", "negative");
  ExpectError(Get("/api/track?since=abc"), 400, "since", "text");
}

TEST_F(HttpServerTest, TrackGrowsWithTheMission) {
  Start();
  FrameRecord f = test::MakeFrame(4, {43.0003, 5.0003}, 0.0002, "used", "");
  TrackPoint p;
  p.seq = 5;
  p.position = {43.0003, 5.0003};
  state_.AddFrame(f, p);
  const json since5 = GetJson("/api/track?since=5");
  EXPECT_EQ(since5["properties"]["from"], 4);
  EXPECT_EQ(since5["properties"]["next"], 6);
  ASSERT_EQ(since5["geometry"]["coordinates"].size(), 2u);
  EXPECT_TRUE(since5["properties"]["times"][1].is_null()) << "a point without time";
  EXPECT_EQ(GetJson("/api/status")["last_pose"]["frame"], 4);
}

TEST_F(HttpServerTest, FramesCoveringAPointNearestFirst) {
  Start();
  const json both = GetJson("/api/frames?lat=43.00002&lon=5.00002");
  EXPECT_EQ(FrameIds(both), (std::vector<int>{0, 1})) << "rejected frame 2 also covers it, but is not listed";
  const json f = both["frames"][0];
  for (const char* key : {"id", "image", "time_s", "lat", "lon", "heading_deg", "pitch_deg", "roll_deg",
                          "altitude_m", "depth_m", "footprint", "image_url", "thumb_url"})
    EXPECT_TRUE(f.contains(key)) << key;
  EXPECT_EQ(f["image"], "frame_0.png");
  EXPECT_EQ(f["footprint"].size(), 4u);
  EXPECT_EQ(f["image_url"], "/api/frames/0/image");
  EXPECT_EQ(f["thumb_url"], "/api/frames/0/image?max=256");

  // Nearer to frame 1's centre, still inside frame 0: the order flips.
  EXPECT_EQ(FrameIds(GetJson("/api/frames?lat=43.00009&lon=5.00009")), (std::vector<int>{1, 0}));
  EXPECT_EQ(FrameIds(GetJson("/api/frames?lat=43.00025&lon=5.00025")), std::vector<int>{1});
  EXPECT_EQ(FrameIds(GetJson("/api/frames?lat=43.00002&lon=5.00002&limit=1")), std::vector<int>{0});
  EXPECT_TRUE(GetJson("/api/frames?lat=44&lon=6")["frames"].empty());
}

TEST_F(HttpServerTest, FramesQueryNeedsAValidPoint) {
  Start();
  ExpectError(Get("/api/frames?lon=5"), 400, "'lat'", "no lat");
  ExpectError(Get("/api/frames"), 400, "'lat'", "nothing");
  ExpectError(Get("/api/frames?lat=43"), 400, "'lon'", "no lon");
  ExpectError(Get("/api/frames?lat=north&lon=5"), 400, "'lat'", "text lat");
  ExpectError(Get("/api/frames?lat=95&lon=5"), 400, "'lat'", "lat out of range");
  ExpectError(Get("/api/frames?lat=43&lon=200"), 400, "'lon'", "lon out of range");
  ExpectError(Get("/api/frames?lat=43&lon=5&limit=x"), 400, "'limit'", "limit");
}

TEST_F(HttpServerTest, OneFrameById) {
  Start();
  const json f = GetJson("/api/frames/1");
  EXPECT_EQ(f["id"], 1);
  EXPECT_EQ(f["image"], "frame_1.jpg");
  EXPECT_DOUBLE_EQ(f["lat"].get<double>(), 43.0001);
  ExpectError(Get("/api/frames/9"), 404, "9", "unknown frame");
  ExpectError(Get("/api/frames/x"), 400, "frame id", "text id");
  // Ids past the int range do not wrap around onto frame 0 or 1.
  ExpectError(Get("/api/frames/4294967296"), 404, "4294967296", "id 2^32");
  ExpectError(Get("/api/frames/4294967297/image"), 404, "4294967297", "id 2^32 + 1");
}

TEST_F(HttpServerTest, FrameImagesAreTheOriginalBytesOrAJpegThumbnail) {
  Start();
  auto png = Get("/api/frames/0/image");
  ASSERT_TRUE(png);
  EXPECT_EQ(png->status, 200);
  EXPECT_EQ(png->get_header_value("Content-Type"), "image/png");
  EXPECT_EQ(png->body, ReadAll(mission_.photo0));

  auto jpg = Get("/api/frames/1/image");
  ASSERT_TRUE(jpg);
  EXPECT_EQ(jpg->get_header_value("Content-Type"), "image/jpeg");
  EXPECT_EQ(jpg->body, ReadAll(mission_.photo1));

  auto thumb = Get("/api/frames/0/image?max=64");
  ASSERT_TRUE(thumb);
  EXPECT_EQ(thumb->status, 200);
  EXPECT_EQ(thumb->get_header_value("Content-Type"), "image/jpeg");
  ASSERT_GE(thumb->body.size(), 2u);
  EXPECT_EQ(static_cast<unsigned char>(thumb->body[0]), 0xff);
  EXPECT_EQ(static_cast<unsigned char>(thumb->body[1]), 0xd8);
  cv::Mat decoded = cv::imdecode(std::vector<uint8_t>(thumb->body.begin(), thumb->body.end()), cv::IMREAD_COLOR);
  ASSERT_FALSE(decoded.empty());
  EXPECT_EQ(decoded.cols, 64);  // 200 x 100 scaled to fit 64
  EXPECT_EQ(decoded.rows, 32);

  ExpectError(Get("/api/frames/9/image"), 404, "9", "unknown frame");
  ExpectError(Get("/api/frames/3/image"), 404, "cannot be read", "photo gone");
  ExpectError(Get("/api/frames/0/image?max=big"), 400, "'max'", "bad max");
}

TEST_F(HttpServerTest, PhotosWhoseRecordedPathIsGoneAreFoundInThePhotoDir) {
  const auto photos = dir_ / "moved";
  std::filesystem::create_directories(photos);
  std::filesystem::copy_file(mission_.photo0, photos / "gone.png");
  ServerOptions o = Options();
  o.photo_dir = photos.string();
  Start(o);
  auto res = Get("/api/frames/3/image");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->body, ReadAll(photos / "gone.png"));
}

// --- detections ------------------------------------------------------------------

TEST_F(HttpServerTest, DetectionsCanBeFiltered) {
  Start();
  const json all = GetJson("/api/detections");
  EXPECT_EQ(all["type"], "FeatureCollection");
  EXPECT_EQ(FeatureIds(all), (std::vector<int64_t>{1, 2}));
  EXPECT_EQ(all["last_seq"], 2);
  EXPECT_EQ(all["features"][0]["geometry"]["coordinates"], json::array({5.0001, 43.0001}));
  EXPECT_EQ(all["features"][0]["properties"]["source"], "recogniser");

  EXPECT_EQ(FeatureIds(GetJson("/api/detections?bbox=5.00005,43.00005,5.0002,43.0002")), std::vector<int64_t>{1});
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?bbox=0,0,1,1")), std::vector<int64_t>{});
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?class=anchor")), std::vector<int64_t>{2});
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?class=anchor,tyre")), (std::vector<int64_t>{1, 2}));
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?min_score=0.9")), std::vector<int64_t>{2});
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?since=1")), std::vector<int64_t>{2});
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?since=2")), std::vector<int64_t>{});
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?class=tyre&min_score=0.5&bbox=5,43,5.001,43.001")),
            std::vector<int64_t>{1});

  ExpectError(Get("/api/detections?bbox=1,2,3"), 400, "'bbox'", "3 numbers");
  ExpectError(Get("/api/detections?bbox=6,43,5,44"), 400, "'bbox'", "west > east");
  ExpectError(Get("/api/detections?min_score=high"), 400, "'min_score'", "text score");
  ExpectError(Get("/api/detections?since=-3"), 400, "'since'", "negative since");
}

TEST_F(HttpServerTest, OneDetectionById) {
  Start();
  const json tyre = GetJson("/api/detections/1");
  EXPECT_EQ(tyre["type"], "Feature");
  EXPECT_EQ(tyre["id"], 1);
  EXPECT_EQ(tyre["properties"]["class"], "tyre");
  EXPECT_DOUBLE_EQ(tyre["properties"]["score"].get<double>(), 0.8);
  EXPECT_EQ(tyre["properties"]["frame_id"], 0);
  ExpectError(Get("/api/detections/99"), 404, "99", "unknown id");
  ExpectError(Get("/api/detections/abc"), 400, "detection id", "text id");
}

TEST_F(HttpServerTest, AMarkIsCreatedChangedAndDeletedAndTheFileFollows) {
  Start();
  auto client = Client();
  json body = Mark(5.002, 43.002, "wreck");
  body["properties"]["note"] = "bow section";
  auto created = client->Post("/api/detections", body.dump(), "application/geo+json");
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201) << created->body;
  EXPECT_EQ(created->get_header_value("Location"), "/api/detections/3");
  const json mark = json::parse(created->body);
  EXPECT_EQ(mark["id"], 3);
  EXPECT_EQ(mark["properties"]["source"], "operator");
  EXPECT_EQ(mark["properties"]["class"], "wreck");
  EXPECT_EQ(mark["properties"]["seq"], 3);
  EXPECT_EQ(GetJson(created->get_header_value("Location")), mark);
  ASSERT_TRUE(StoredDetections().count(3)) << "written through to the MBTiles file";
  EXPECT_EQ(StoredDetections().at(3).note, "bow section");

  auto patched = client->Patch("/api/detections/3", json{{"note", "stern too"}, {"score", 0.7}}.dump(),
                               "application/json");
  ASSERT_TRUE(patched);
  ASSERT_EQ(patched->status, 200) << patched->body;
  EXPECT_EQ(json::parse(patched->body)["properties"]["note"], "stern too");
  EXPECT_EQ(json::parse(patched->body)["properties"]["seq"], 4);
  EXPECT_EQ(StoredDetections().at(3).note, "stern too");
  EXPECT_DOUBLE_EQ(StoredDetections().at(3).score, 0.7);

  json moved = Mark(5.004, 43.004, "wreck");
  auto moved_res = client->Patch("/api/detections/3", moved.dump(), "application/geo+json");
  ASSERT_TRUE(moved_res);
  ASSERT_EQ(moved_res->status, 200) << moved_res->body;
  EXPECT_DOUBLE_EQ(StoredDetections().at(3).position.lat, 43.004);
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?since=3")), std::vector<int64_t>{3});

  auto deleted = client->Delete("/api/detections/3");
  ASSERT_TRUE(deleted);
  EXPECT_EQ(deleted->status, 204);
  EXPECT_TRUE(deleted->body.empty());
  ExpectError(Get("/api/detections/3"), 404, "3", "deleted");
  EXPECT_EQ(StoredDetections().count(3), 0u);
  ExpectError(client->Delete("/api/detections/3"), 404, "3", "deleted twice");
  ExpectError(client->Patch("/api/detections/3", "{}", "application/json"), 404, "3", "patch deleted");
}

TEST_F(HttpServerTest, MarksSurviveAServerRestart) {
  Start();
  auto created = Client()->Post("/api/detections", Mark(5.003, 43.003, "net").dump(), "application/json");
  ASSERT_TRUE(created);
  ASSERT_EQ(created->status, 201);
  server_->Stop();
  server_.reset();
  registry_.reset();
  writer_.reset();
  tiles_.reset();

  EventHub events;
  TileSource tiles(mission_.path.string(), 1);
  MBTilesStore writer(mission_.path.string());
  MissionState state;
  state.Load(writer);
  DetectionRegistry registry(&writer, &events);
  registry.Load(writer);
  HttpServer again(Options(), &tiles, &state, &registry, &events);
  again.Bind();
  again.Start();
  httplib::Client client("127.0.0.1", again.port());
  client.set_read_timeout(60);
  auto res = client.Get("/api/detections?class=net");
  ASSERT_TRUE(res);
  const json found = json::parse(res->body);
  EXPECT_EQ(FeatureIds(found), std::vector<int64_t>{3});
  again.Stop();
}

TEST_F(HttpServerTest, WritesNeedTheTokenWhenTheServerHasOne) {
  ServerOptions o = Options();
  o.token = "s3cret";
  Start(o);
  auto client = Client();
  const std::string body = Mark(5.002, 43.002, "wreck").dump();

  auto anonymous = client->Post("/api/detections", body, "application/json");
  ExpectError(anonymous, 401, "Bearer", "no token");
  EXPECT_NE(anonymous->get_header_value("WWW-Authenticate").find("Bearer"), std::string::npos);
  ExpectError(client->Post("/api/detections", {{"Authorization", "Bearer wrong!"}}, body, "application/json"), 401,
              "Bearer", "wrong token");
  ExpectError(client->Post("/api/detections", {{"Authorization", "Bearer s3cre"}}, body, "application/json"), 401,
              "Bearer", "prefix of the token");
  ExpectError(client->Post("/api/detections", {{"Authorization", "s3cret"}}, body, "application/json"), 401,
              "Bearer", "no scheme");
  ExpectError(client->Patch("/api/detections/2", json{{"note", "x"}}.dump(), "application/json"), 401, "Bearer",
              "patch without token");
  ExpectError(client->Delete("/api/detections/2"), 401, "Bearer", "delete without token");
  EXPECT_EQ(StoredDetections().size(), 2u);
  EXPECT_EQ(StoredDetections().at(2).note, "seen by the diver");

  const httplib::Headers auth = {{"Authorization", "Bearer s3cret"}};
  auto created = client->Post("/api/detections", auth, body, "application/json");
  ASSERT_TRUE(created);
  EXPECT_EQ(created->status, 201) << created->body;
  auto patched = client->Patch("/api/detections/2", auth, json{{"note", "x"}}.dump(), "application/json");
  ASSERT_TRUE(patched);
  EXPECT_EQ(patched->status, 200) << patched->body;
  auto deleted = client->Delete("/api/detections/2", auth);
  ASSERT_TRUE(deleted);
  EXPECT_EQ(deleted->status, 204);

  // Reading never needs the token.
  EXPECT_EQ(FeatureIds(GetJson("/api/detections")), (std::vector<int64_t>{1, 3}));
}

TEST_F(HttpServerTest, TheRecognisersDetectionsCannotBeChangedOrDeleted) {
  Start();
  auto client = Client();
  ExpectError(client->Patch("/api/detections/1", json{{"class", "bin"}}.dump(), "application/json"), 403,
              "recogniser", "patch");
  ExpectError(client->Delete("/api/detections/1"), 403, "recogniser", "delete");
  EXPECT_EQ(GetJson("/api/detections/1")["properties"]["class"], "tyre");
  EXPECT_EQ(StoredDetections().at(1).class_name, "tyre");
}

TEST_F(HttpServerTest, AReadOnlyMissionRefusesWrites) {
  Start(Options(), /*writable=*/false);
  ExpectError(Client()->Post("/api/detections", Mark(5, 43, "x").dump(), "application/json"), 403, "read-only",
              "post");
  ExpectError(Client()->Delete("/api/detections/2"), 403, "read-only", "delete");
  EXPECT_EQ(StoredDetections().size(), 2u);
}

TEST_F(HttpServerTest, BadBodiesAre400NamingWhatIsWrong) {
  Start();
  auto client = Client();
  ExpectError(client->Post("/api/detections", "{\"type\": \"Feature\",", "application/json"), 400, "body",
              "truncated JSON");
  ExpectError(client->Post("/api/detections", "", "application/json"), 400, "body", "empty body");
  json no_class = Mark(5, 43, "x");
  no_class["properties"].erase("class");
  ExpectError(client->Post("/api/detections", no_class.dump(), "application/json"), 400, "properties.class",
              "no class");
  json polygon = Mark(5, 43, "x");
  polygon["geometry"] = {{"type", "Polygon"}, {"coordinates", json::array()}};
  ExpectError(client->Post("/api/detections", polygon.dump(), "application/json"), 400, "geometry", "polygon");
  ExpectError(client->Post("/api/detections", Mark(5, 100, "x").dump(), "application/json"), 400,
              "geometry.coordinates", "lat 100");
  json score = Mark(5, 43, "x");
  score["properties"]["score"] = 2;
  ExpectError(client->Post("/api/detections", score.dump(), "application/json"), 400, "properties.score", "score");
  ExpectError(client->Post("/api/detections", R"({"type": 7})", "application/json"), 400, "Feature", "numeric type");
  ExpectError(client->Patch("/api/detections/2", "not json", "application/json"), 400, "body", "patch not JSON");
  ExpectError(client->Patch("/api/detections/2", json{{"colour", "red"}}.dump(), "application/json"), 400,
              "properties.colour", "unknown property");
  EXPECT_EQ(StoredDetections().size(), 2u);
  EXPECT_EQ(StoredDetections().at(2).class_name, "anchor");
}

TEST_F(HttpServerTest, BodiesOver64KiBAreRefused) {
  Start();
  json body = Mark(5, 43, "x");
  body["properties"]["note"] = std::string(70 * 1024, 'n');
  auto res = Client()->Post("/api/detections", body.dump(), "application/json");
  ASSERT_TRUE(res) << "the server answers instead of dropping the connection";
  EXPECT_EQ(res->status, 413) << res->body;
  EXPECT_TRUE(json::parse(res->body, nullptr, false).contains("error")) << res->body;
  EXPECT_EQ(StoredDetections().size(), 2u);
  // The server still answers afterwards.
  EXPECT_EQ(FeatureIds(GetJson("/api/detections")), (std::vector<int64_t>{1, 2}));
}

// --- live events ---------------------------------------------------------------------

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
       {"/../secret.txt", "/js/../../secret.txt", "/%2e%2e/secret.txt", "/%2E%2E/secret.txt", "/js/%2e%2e/%2e%2e/secret.txt",
        "/..%2fsecret.txt", "/%2e%2e%2fsecret.txt", "/js/..%2f..%2fsecret.txt", "/..\\secret.txt",
        "/%2e%2e%5csecret.txt", "//../secret.txt", "/./../secret.txt", "/js/./../../secret.txt"}) {
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
