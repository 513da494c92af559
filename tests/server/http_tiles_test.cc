// Tiles and TileJSON over HTTP: bytes, ETags and 304s, 204s and 400s, layers, folders.
#include "tests/server/http_test_fixture.h"

namespace seamap::server {
namespace {

using namespace http_test;

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
  const std::vector<std::pair<std::string, std::string>> cases = {{"/tiles/31/0/0.png", "zoom"},
                                                                  {"/tiles/3/8/0.png", "2^z"},
                                                                  {"/tiles/3/0/8.png", "2^z"},
                                                                  {"/tiles/a/0/0.png", "non-negative integers"},
                                                                  {"/tiles/3/-1/2.png", "non-negative"},
                                                                  {"/tiles/3/4/2", "{y}.{ext}"},
                                                                  {"/tiles/3/4.png", "tile path"},
                                                                  {"/tiles/enhanced/3/4/5/6.png", "tile path"},
                                                                  {"/tiles/3/4/.png", "tile path"},
                                                                  {"/tiles/99999999999/0/0.png", "tile path"},
                                                                  {"/tiles/", "tile path"},
                                                                  {"/tiles/3/4/2.png/", "tile path"}};
  for (const auto& [path, needle] : cases) ExpectError(Get(path), 400, needle, path);
}

TEST_F(HttpServerTest, AnotherExtensionThanTheMissionsFormatIs404) {
  Start();
  ExpectError(Get("/tiles/3/4/2.jpg"), 404, ".png or .webp", "jpg");
  ExpectError(Get("/tiles/3/4/2.gif"), 404, ".png", "gif");
  ExpectError(Get("/tiles/enhanced/3/4/2.jpeg"), 404, ".png", "layer jpeg");
}

// A weak link asks for .webp: the PNG tile transcoded (alpha kept), with an
// ETag tied to the PNG's, so a rewritten tile is never served stale.
TEST_F(HttpServerTest, PngTilesAreAlsoServedAsWebpForAWeakLink) {
  Start();
  const auto png = mission_.tiles.at(TileId{3, 4, 2});
  auto res = Get("/tiles/3/4/2.webp");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "image/webp");
  EXPECT_EQ(res->body.compare(0, 4, "RIFF"), 0);
  EXPECT_EQ(res->body.compare(8, 4, "WEBP"), 0);
  // Same picture, within what lossy coding allows.
  auto mean_difference = [](const std::string& webp, const std::vector<uint8_t>& png_bytes) {
    const cv::Mat a = cv::imdecode(std::vector<uint8_t>(webp.begin(), webp.end()), cv::IMREAD_COLOR);
    const cv::Mat b = cv::imdecode(png_bytes, cv::IMREAD_COLOR);
    if (a.empty() || a.size() != b.size()) return 1e9;
    cv::Mat diff;
    cv::absdiff(a, b, diff);
    return cv::mean(diff)[0] + cv::mean(diff)[1] + cv::mean(diff)[2];
  };
  EXPECT_LE(mean_difference(res->body, png), 15.0);

  const std::string etag = res->get_header_value("ETag");
  const std::string png_etag = QuotedVersion(png);
  EXPECT_EQ(etag, png_etag.substr(0, png_etag.size() - 1) + ".webp\"");
  auto again = Get("/tiles/3/4/2.webp", {{"If-None-Match", etag}});
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 304);

  const auto replaced = test::Png(16, 16, 250);
  writer_->PutTile(TileId{3, 4, 2}, replaced);
  writer_->Flush();
  tiles_->Invalidate("", TileId{3, 4, 2});
  auto fresh = Get("/tiles/3/4/2.webp", {{"If-None-Match", etag}});
  ASSERT_TRUE(fresh);
  EXPECT_EQ(fresh->status, 200) << "the browser's WebP copy is of the old tile";
  EXPECT_LE(mean_difference(fresh->body, replaced), 15.0);
  EXPECT_GT(mean_difference(fresh->body, png), 100.0) << "the new tile, not the old one";

  auto layer = Get("/tiles/enhanced/3/4/2.webp");
  ASSERT_TRUE(layer);
  EXPECT_EQ(layer->status, 200);
  EXPECT_EQ(Get("/tiles/3/7/7.webp")->status, 204) << "no tile there";
  EXPECT_EQ(json::parse(Get("/tiles.json")->body)["seamap_formats"], json::array({"png", "webp"}));
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
  EXPECT_EQ(tj["tiles"][0], "http://127.0.0.1:" + std::to_string(server_->port()) + "/tiles/enhanced/{z}/{x}/{y}.png");
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

}  // namespace
}  // namespace seamap::server
