// The mission API over HTTP: status, track, frames and photos, detections and marks with the token.
#include "tests/server/http_test_fixture.h"

namespace seamap::server {
namespace {

using namespace http_test;

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
  for (const char* key : {"id", "image", "time_s", "lat", "lon", "heading_deg", "pitch_deg", "roll_deg", "altitude_m",
                          "depth_m", "footprint", "image_url", "thumb_url"})
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

// The footprints layer: every used frame's outline meeting the view, compact.
TEST_F(HttpServerTest, FootprintsMeetingABoxAsPolygons) {
  Start();
  const json all = GetJson("/api/footprints?bbox=4.999,42.999,5.001,43.001");
  ASSERT_EQ(all["type"], "FeatureCollection");
  std::vector<int> ids;
  for (const auto& f : all["features"]) ids.push_back(f["id"].get<int>());
  EXPECT_EQ(ids, (std::vector<int>{0, 1})) << "the rejected frame 2 is not drawn, frame 3 is elsewhere";
  const json f0 = all["features"][0];
  EXPECT_EQ(f0["geometry"]["type"], "Polygon");
  const json ring = f0["geometry"]["coordinates"][0];
  ASSERT_EQ(ring.size(), 5u);
  EXPECT_EQ(ring[0], ring[4]) << "a closed ring";
  EXPECT_EQ(f0["properties"]["image"], "frame_0.png");
  EXPECT_FALSE(f0["properties"].contains("footprint")) << "outlines only, not whole frame records";
  const json frame0 = GetJson("/api/frames/0");
  EXPECT_EQ(ring[0], frame0["footprint"][0]);
  // A box that only frame 1's footprint reaches (it extends further north-east).
  std::vector<int> ne;
  const json ne_answer = GetJson("/api/footprints?bbox=5.00025,43.00025,5.001,43.001");
  for (const auto& f : ne_answer["features"]) ne.push_back(f["id"].get<int>());
  EXPECT_EQ(ne, std::vector<int>{1}) << ne_answer.dump();
  EXPECT_TRUE(GetJson("/api/footprints?bbox=6,44,6.1,44.1")["features"].empty());
  EXPECT_EQ(GetJson("/api/footprints?bbox=4.999,42.999,5.001,43.001&limit=1")["features"].size(), 1u);
  ExpectError(Get("/api/footprints"), 400, "'bbox'", "no bbox");
  ExpectError(Get("/api/footprints?bbox=1,2,3"), 400, "'bbox'", "3 numbers");
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

  auto patched =
      client->Patch("/api/detections/3", json{{"note", "stern too"}, {"score", 0.7}}.dump(), "application/json");
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
  ExpectError(client->Post("/api/detections", {{"Authorization", "s3cret"}}, body, "application/json"), 401, "Bearer",
              "no scheme");
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
  ExpectError(client->Patch("/api/detections/1", json{{"class", "bin"}}.dump(), "application/json"), 403, "recogniser",
              "patch");
  ExpectError(client->Delete("/api/detections/1"), 403, "recogniser", "delete");
  EXPECT_EQ(GetJson("/api/detections/1")["properties"]["class"], "tyre");
  EXPECT_EQ(StoredDetections().at(1).class_name, "tyre");
}

TEST_F(HttpServerTest, AReadOnlyMissionRefusesWrites) {
  Start(Options(), /*writable=*/false);
  ExpectError(Client()->Post("/api/detections", Mark(5, 43, "x").dump(), "application/json"), 403, "read-only", "post");
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

}  // namespace
}  // namespace seamap::server
