#include "server/detection_registry.h"

#include <gtest/gtest.h>

#include "core/mission/detection_book.h"
#include "server/api_error.h"
#include "tests/server/test_mission.h"
#include "tests/testing/temp_dir.h"

namespace seamap::server {
namespace {

using nlohmann::json;

// The ApiError a call throws (status 0 and no message when it throws none).
template <typename F>
std::pair<int, std::string> ErrorOf(F f) {
  try {
    f();
  } catch (const ApiError& e) {
    return {e.status(), e.what()};
  }
  return {0, ""};
}

#define EXPECT_API_ERROR(call, status, needle)                                          \
  do {                                                                                  \
    auto err = ErrorOf([&] { call; });                                                  \
    EXPECT_EQ(err.first, status) << err.second;                                         \
    EXPECT_NE(err.second.find(needle), std::string::npos) << "message: " << err.second; \
  } while (0)

json Mark(double lon, double lat, const std::string& cls) {
  return {{"type", "Feature"},
          {"geometry", {{"type", "Point"}, {"coordinates", {lon, lat}}}},
          {"properties", {{"class", cls}}}};
}

std::vector<int64_t> Ids(const json& collection) {
  std::vector<int64_t> ids;
  for (const auto& f : collection["features"]) ids.push_back(f["id"].get<int64_t>());
  return ids;
}

class DetectionRegistryTest : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = std::make_unique<MBTilesStore>(mission_.path.string());
    registry_ = std::make_unique<DetectionRegistry>(store_.get(), &events_);
    registry_->Load(*store_);
  }
  // What a fresh reader of the file sees.
  std::map<int64_t, Detection> Stored() const {
    MBTilesStore reader(mission_.path.string(), MBTilesStore::Mode::kReadOnly);
    std::map<int64_t, Detection> out;
    for (const auto& d : reader.Detections()) out[d.id] = d;
    return out;
  }
  json LastEvent() {
    auto events = events_.WaitAfter(events_.LastId() - 1, std::chrono::milliseconds(0));
    EXPECT_FALSE(events.empty());
    if (events.empty()) return nullptr;
    EXPECT_EQ(events.back().type, "detection");
    return json::parse(events.back().data);
  }

  seamap::testing::TempDir dir_;
  test::TestMission mission_ = test::WriteTestMission(dir_.path());
  EventHub events_;
  std::unique_ptr<MBTilesStore> store_;
  std::unique_ptr<DetectionRegistry> registry_;
};

TEST(ParseDetectionFilter, ReadsEveryParameter) {
  auto f = ParseDetectionFilter(std::string("4.5,42.5,5.5,43.5"), std::string("tyre,,anchor"), std::string("0.25"),
                                std::string("7"));
  ASSERT_TRUE(f.bbox);
  EXPECT_DOUBLE_EQ(f.bbox->west, 4.5);
  EXPECT_DOUBLE_EQ(f.bbox->south, 42.5);
  EXPECT_DOUBLE_EQ(f.bbox->east, 5.5);
  EXPECT_DOUBLE_EQ(f.bbox->north, 43.5);
  EXPECT_EQ(f.classes, (std::set<std::string>{"tyre", "anchor"}));
  EXPECT_DOUBLE_EQ(*f.min_score, 0.25);
  EXPECT_EQ(*f.since, 7);

  auto none = ParseDetectionFilter(std::nullopt, std::nullopt, std::nullopt, std::nullopt);
  EXPECT_FALSE(none.bbox);
  EXPECT_TRUE(none.classes.empty());
  EXPECT_FALSE(none.min_score);
  EXPECT_FALSE(none.since);
}

TEST(ParseDetectionFilter, ErrorsNameTheParameter) {
  const std::nullopt_t no = std::nullopt;
  EXPECT_API_ERROR(ParseDetectionFilter(std::string("1,2,3"), no, no, no), 400, "'bbox'");
  EXPECT_API_ERROR(ParseDetectionFilter(std::string("1,2,3,4,5"), no, no, no), 400, "'bbox'");
  EXPECT_API_ERROR(ParseDetectionFilter(std::string("5,2,3,4"), no, no, no), 400, "west <= east");
  EXPECT_API_ERROR(ParseDetectionFilter(std::string("1,5,3,4"), no, no, no), 400, "south <= north");
  EXPECT_API_ERROR(ParseDetectionFilter(std::string("a,2,3,4"), no, no, no), 400, "'bbox'");
  EXPECT_API_ERROR(ParseDetectionFilter(no, no, std::string("high"), no), 400, "'min_score'");
  EXPECT_API_ERROR(ParseDetectionFilter(no, no, std::string("nan"), no), 400, "'min_score'");
  EXPECT_API_ERROR(ParseDetectionFilter(no, no, std::string("0.5x"), no), 400, "'min_score'");
  EXPECT_API_ERROR(ParseDetectionFilter(no, no, no, std::string("-1")), 400, "'since'");
  EXPECT_API_ERROR(ParseDetectionFilter(no, no, no, std::string("1.5")), 400, "'since'");
  EXPECT_API_ERROR(ParseDetectionFilter(no, no, no, std::string("")), 400, "'since'");
}

TEST(DetectionFeature, IsAGeoJsonPointFeatureWithLonLat) {
  Detection d;
  d.id = 9;
  d.class_name = "cable";
  d.score = 0.4;
  d.position = {43.5, 5.25};
  d.source = "recogniser";
  d.frame_id = 12;
  d.seq = 4;
  const json f = DetectionFeature(d);
  EXPECT_EQ(f["type"], "Feature");
  EXPECT_EQ(f["id"], 9);
  EXPECT_EQ(f["geometry"]["type"], "Point");
  EXPECT_EQ(f["geometry"]["coordinates"], json::array({5.25, 43.5}));
  EXPECT_EQ(f["properties"]["class"], "cable");
  EXPECT_EQ(f["properties"]["source"], "recogniser");
  EXPECT_EQ(f["properties"]["frame_id"], 12);
  EXPECT_TRUE(f["properties"]["time_s"].is_null());
  EXPECT_EQ(f["properties"]["seq"], 4);
  d.frame_id.reset();
  EXPECT_TRUE(DetectionFeature(d)["properties"]["frame_id"].is_null());
}

TEST_F(DetectionRegistryTest, QueryWithoutFilterListsEverythingAndTheLastSeq) {
  const json all = registry_->Query({});
  EXPECT_EQ(all["type"], "FeatureCollection");
  EXPECT_EQ(Ids(all), (std::vector<int64_t>{1, 2}));
  EXPECT_EQ(all["last_seq"], 2);
  EXPECT_TRUE(registry_->writable());
}

TEST_F(DetectionRegistryTest, QueryFilters) {
  DetectionFilter bbox;
  bbox.bbox = LatLonBounds{5.00005, 43.00005, 5.0002, 43.0002};  // around the tyre only
  EXPECT_EQ(Ids(registry_->Query(bbox)), std::vector<int64_t>{1});

  DetectionFilter edge;  // the bbox is closed: a point on its edge is inside
  edge.bbox = LatLonBounds{5.0005, 43.0005, 5.001, 43.001};
  EXPECT_EQ(Ids(registry_->Query(edge)), std::vector<int64_t>{2});

  DetectionFilter classes;
  classes.classes = {"anchor", "wreck"};
  EXPECT_EQ(Ids(registry_->Query(classes)), std::vector<int64_t>{2});

  DetectionFilter score;
  score.min_score = 0.9;
  EXPECT_EQ(Ids(registry_->Query(score)), std::vector<int64_t>{2});
  score.min_score = 0.8;  // inclusive
  EXPECT_EQ(Ids(registry_->Query(score)).size(), 2u);

  DetectionFilter since;
  since.since = 1;
  EXPECT_EQ(Ids(registry_->Query(since)), std::vector<int64_t>{2});
  since.since = 2;
  EXPECT_TRUE(Ids(registry_->Query(since)).empty());

  DetectionFilter both;
  both.classes = {"tyre"};
  both.min_score = 0.9;
  EXPECT_TRUE(Ids(registry_->Query(both)).empty());
}

TEST_F(DetectionRegistryTest, GetById) {
  auto tyre = registry_->Get(1);
  ASSERT_TRUE(tyre);
  EXPECT_EQ((*tyre)["properties"]["class"], "tyre");
  EXPECT_EQ((*tyre)["properties"]["frame_id"], 0);
  EXPECT_DOUBLE_EQ((*tyre)["properties"]["time_s"].get<double>(), 12.5);
  EXPECT_FALSE(registry_->Get(3));
}

TEST_F(DetectionRegistryTest, CreateStoresAnOperatorMarkAndAnnouncesIt) {
  json body = Mark(5.002, 43.002, "wreck");
  body["properties"]["note"] = "bow section";
  body["properties"]["score"] = 0.6;
  body["properties"]["time_s"] = 33.5;
  body["properties"]["source"] = "recogniser";  // read-only: ignored
  body["properties"]["seq"] = 99;
  const json created = registry_->Create(body);

  EXPECT_EQ(created["id"], 3);
  EXPECT_EQ(created["properties"]["id"], 3);
  EXPECT_EQ(created["properties"]["source"], "operator");
  EXPECT_EQ(created["properties"]["class"], "wreck");
  EXPECT_EQ(created["properties"]["note"], "bow section");
  EXPECT_DOUBLE_EQ(created["properties"]["score"].get<double>(), 0.6);
  EXPECT_DOUBLE_EQ(created["properties"]["time_s"].get<double>(), 33.5);
  EXPECT_EQ(created["properties"]["seq"], 3);
  EXPECT_EQ(created["geometry"]["coordinates"], json::array({5.002, 43.002}));
  EXPECT_EQ(created["properties"]["created"].get<std::string>().size(), 20u);  // 2024-05-01T10:00:00Z
  EXPECT_EQ(created["properties"]["created"], created["properties"]["updated"]);

  const auto stored = Stored();
  ASSERT_TRUE(stored.count(3));
  EXPECT_EQ(stored.at(3).class_name, "wreck");
  EXPECT_EQ(stored.at(3).source, "operator");
  EXPECT_DOUBLE_EQ(stored.at(3).position.lat, 43.002);

  const json event = LastEvent();
  EXPECT_EQ(event["action"], "created");
  EXPECT_EQ(event["id"], 3);
  EXPECT_EQ(event["feature"], created);
  EXPECT_EQ(registry_->Query({})["last_seq"], 3);
}

TEST_F(DetectionRegistryTest, CreateDefaultsScoreToOneAndAcceptsAnAltitude) {
  json body = Mark(5, 43, "rock");
  body["geometry"]["coordinates"] = {5.0, 43.0, -30.0};
  const json created = registry_->Create(body);
  EXPECT_DOUBLE_EQ(created["properties"]["score"].get<double>(), 1.0);
  EXPECT_EQ(created["properties"]["note"], "");
  EXPECT_TRUE(created["properties"]["frame_id"].is_null());
}

TEST_F(DetectionRegistryTest, CreateRejectsBadBodiesNamingTheProperty) {
  EXPECT_API_ERROR(registry_->Create(json::array()), 400, "Feature");
  EXPECT_API_ERROR(registry_->Create(json{{"type", "FeatureCollection"}}), 400, "Feature");
  json no_class = Mark(5, 43, "x");
  no_class["properties"].erase("class");
  EXPECT_API_ERROR(registry_->Create(no_class), 400, "properties.class");
  EXPECT_API_ERROR(registry_->Create(Mark(5, 43, "")), 400, "properties.class");
  EXPECT_API_ERROR(registry_->Create(Mark(5, 43, std::string(65, 'a'))), 400, "properties.class");
  json no_geometry = Mark(5, 43, "x");
  no_geometry.erase("geometry");
  EXPECT_API_ERROR(registry_->Create(no_geometry), 400, "geometry");
  json polygon = Mark(5, 43, "x");
  polygon["geometry"]["type"] = "Polygon";
  EXPECT_API_ERROR(registry_->Create(polygon), 400, "geometry");
  EXPECT_API_ERROR(registry_->Create(Mark(5, 91, "x")), 400, "geometry.coordinates");
  EXPECT_API_ERROR(registry_->Create(Mark(181, 43, "x")), 400, "geometry.coordinates");
  json text_coords = Mark(5, 43, "x");
  text_coords["geometry"]["coordinates"] = {"5", "43"};
  EXPECT_API_ERROR(registry_->Create(text_coords), 400, "geometry.coordinates");
  json one_coord = Mark(5, 43, "x");
  one_coord["geometry"]["coordinates"] = {5.0};
  EXPECT_API_ERROR(registry_->Create(one_coord), 400, "geometry.coordinates");
  json score = Mark(5, 43, "x");
  score["properties"]["score"] = 1.5;
  EXPECT_API_ERROR(registry_->Create(score), 400, "properties.score");
  score["properties"]["score"] = "high";
  EXPECT_API_ERROR(registry_->Create(score), 400, "properties.score");
  json note = Mark(5, 43, "x");
  note["properties"]["note"] = 7;
  EXPECT_API_ERROR(registry_->Create(note), 400, "properties.note");
  note["properties"]["note"] = std::string(4001, 'n');
  EXPECT_API_ERROR(registry_->Create(note), 400, "properties.note");
  json time = Mark(5, 43, "x");
  time["properties"]["time_s"] = "noon";
  EXPECT_API_ERROR(registry_->Create(time), 400, "properties.time_s");
  json unknown = Mark(5, 43, "x");
  unknown["properties"]["colour"] = "red";
  EXPECT_API_ERROR(registry_->Create(unknown), 400, "properties.colour");
  json props = Mark(5, 43, "x");
  props["properties"] = "x";
  EXPECT_API_ERROR(registry_->Create(props), 400, "properties");

  // Nothing was stored or announced.
  EXPECT_EQ(Ids(registry_->Query({})), (std::vector<int64_t>{1, 2}));
  EXPECT_EQ(Stored().size(), 2u);
  EXPECT_EQ(events_.LastId(), 0u);
}

// Regression: a "type" that is not a string threw nlohmann's type_error (a 500).
TEST_F(DetectionRegistryTest, ANonStringTypeIsABadBody) {
  EXPECT_API_ERROR(registry_->Create(json{{"type", 1}}), 400, "Feature");
  json geometry_type = Mark(5, 43, "x");
  geometry_type["geometry"]["type"] = json::array({"Point"});
  EXPECT_API_ERROR(registry_->Create(geometry_type), 400, "geometry");
  EXPECT_API_ERROR(registry_->Update(2, json{{"type", nullptr}, {"note", "x"}}), 400, "properties.type");
  EXPECT_EQ(events_.LastId(), 0u);
}

TEST_F(DetectionRegistryTest, UpdateChangesAnOperatorMark) {
  const json before = *registry_->Get(2);
  const json patched = registry_->Update(2, {{"note", "checked"}, {"score", 0.5}});
  EXPECT_EQ(patched["properties"]["note"], "checked");
  EXPECT_DOUBLE_EQ(patched["properties"]["score"].get<double>(), 0.5);
  EXPECT_EQ(patched["properties"]["class"], "anchor");
  EXPECT_EQ(patched["properties"]["created"], before["properties"]["created"]);
  EXPECT_NE(patched["properties"]["updated"], before["properties"]["updated"]);
  EXPECT_EQ(patched["properties"]["seq"], 3);
  EXPECT_EQ(patched["geometry"], before["geometry"]);

  // As a Feature: geometry and properties.
  json feature = Mark(5.003, 43.003, "chain");
  const json moved = registry_->Update(2, feature);
  EXPECT_EQ(moved["geometry"]["coordinates"], json::array({5.003, 43.003}));
  EXPECT_EQ(moved["properties"]["class"], "chain");
  EXPECT_EQ(moved["properties"]["note"], "checked");
  EXPECT_EQ(moved["properties"]["seq"], 4);

  EXPECT_EQ(Stored().at(2).class_name, "chain");
  EXPECT_DOUBLE_EQ(Stored().at(2).position.lon, 5.003);
  const json event = LastEvent();
  EXPECT_EQ(event["action"], "updated");
  EXPECT_EQ(event["feature"], moved);

  DetectionFilter since;
  since.since = 2;
  EXPECT_EQ(Ids(registry_->Query(since)), std::vector<int64_t>{2});
}

TEST_F(DetectionRegistryTest, UpdateRejections) {
  EXPECT_API_ERROR(registry_->Update(1, {{"class", "rock"}}), 403, "only its status and note");
  EXPECT_API_ERROR(registry_->Update(42, {{"note", "x"}}), 404, "42");
  EXPECT_API_ERROR(registry_->Update(2, json::array()), 400, "body");
  EXPECT_API_ERROR(registry_->Update(2, {{"class", ""}}), 400, "properties.class");
  json bad_geometry = Mark(5, 43, "x");
  bad_geometry["geometry"]["coordinates"] = {5.0, -95.0};
  EXPECT_API_ERROR(registry_->Update(2, bad_geometry), 400, "geometry.coordinates");
  // The recogniser's detection is unchanged, and a failed patch changed nothing.
  EXPECT_EQ((*registry_->Get(1))["properties"]["class"], "tyre");
  EXPECT_EQ((*registry_->Get(2))["properties"]["class"], "anchor");
  EXPECT_EQ((*registry_->Get(2))["properties"]["seq"], 2);
  EXPECT_EQ(events_.LastId(), 0u);
}

TEST_F(DetectionRegistryTest, DeleteRemovesAMarkFromMemoryAndFile) {
  registry_->Delete(2);
  EXPECT_FALSE(registry_->Get(2));
  EXPECT_EQ(Stored().count(2), 0u);
  EXPECT_EQ(Stored().count(1), 1u);
  const json event = LastEvent();
  EXPECT_EQ(event["action"], "deleted");
  EXPECT_EQ(event["id"], 2);
  EXPECT_TRUE(event["feature"].is_null());
  EXPECT_EQ(registry_->Query({})["last_seq"], 3) << "a deletion is a change too";

  EXPECT_API_ERROR(registry_->Delete(2), 404, "2");
  EXPECT_API_ERROR(registry_->Delete(1), 403, "recogniser");
  EXPECT_TRUE(registry_->Get(1));
}

TEST_F(DetectionRegistryTest, IdsAreNeverReusedAfterADelete) {
  const int64_t a = registry_->Create(Mark(5, 43, "a"))["id"];
  registry_->Delete(a);
  const int64_t b = registry_->Create(Mark(5, 43, "b"))["id"];
  EXPECT_GT(b, a);
}

TEST_F(DetectionRegistryTest, ContinuesNumberingAfterReload) {
  registry_->Create(Mark(5, 43, "a"));             // id 3, seq 3
  DetectionRegistry again(store_.get(), nullptr);  // no event hub: nothing announced
  again.Load(*store_);
  EXPECT_EQ(again.Query({})["last_seq"], 3);
  const json next = again.Create(Mark(5, 43, "b"));
  EXPECT_EQ(next["id"], 4);
  EXPECT_EQ(next["properties"]["seq"], 4);
}

TEST_F(DetectionRegistryTest, AReadOnlyMissionRefusesWrites) {
  DetectionRegistry read_only(nullptr, &events_);
  read_only.Load(*store_);
  EXPECT_FALSE(read_only.writable());
  EXPECT_EQ(Ids(read_only.Query({})), (std::vector<int64_t>{1, 2}));
  EXPECT_API_ERROR(read_only.Create(Mark(5, 43, "x")), 403, "read-only");
  EXPECT_API_ERROR(read_only.Update(2, {{"note", "x"}}), 403, "read-only");
  EXPECT_API_ERROR(read_only.Delete(2), 403, "read-only");
}

TEST_F(DetectionRegistryTest, TakesInWhatAnotherProcessWrote) {
  // stereo-locate --map in another process: its own connection to the file.
  const int64_t marked = registry_->Create(Mark(5, 43, "a"))["id"];  // id 3, seq 3
  registry_->Delete(marked);                                         // a tombstone at seq 4
  Detection located;
  {
    MBTilesStore other(mission_.path.string());
    located.class_name = "wellhead";
    located.source = "stereo";
    located.position = {43.01, 5.01};
    located.heading_deg = 30;
    located = PublishFound(other, {located}, "wellhead.json", {"wellhead"}).at(0);
    Detection changed = other.Detections().at(1);  // id 2, moved by the other process
    changed.position.lat += 0.001;
    changed.seq = located.seq + 1;
    other.PutDetection(changed);
    other.DeleteDetection(1);
    other.Flush();
  }
  EXPECT_EQ(located.id, marked);  // numbered from the file, where the deleted mark's id is free again
  EXPECT_LE(located.seq, 4);
  const int64_t before = events_.LastId();
  registry_->Refresh(*store_);
  std::vector<std::string> actions;
  for (const auto& e : events_.WaitAfter(before, std::chrono::milliseconds(0)))
    actions.push_back(json::parse(e.data)["action"].get<std::string>() + " " +
                      std::to_string(json::parse(e.data)["id"].get<int64_t>()));
  EXPECT_EQ(actions, (std::vector<std::string>{"updated 2", "created 3", "deleted 1"}));
  const json all = registry_->Query({});
  EXPECT_EQ(Ids(all), (std::vector<int64_t>{2, 3}));
  // A browser that had seen everything up to our tombstone (seq 4) still gets the new ones.
  DetectionFilter since;
  since.since = 4;
  EXPECT_EQ(Ids(registry_->Query(since)), (std::vector<int64_t>{2, 3}));
  EXPECT_EQ(registry_->Get(3).value()["properties"]["heading_deg"], 30);
  EXPECT_EQ(registry_->Classes().back(), "wellhead");
  // Nothing more the second time.
  const int64_t after = events_.LastId();
  registry_->Refresh(*store_);
  EXPECT_EQ(events_.LastId(), after);

  // Another write by the other process, not yet refreshed: a PATCH does not put
  // back the old position, and a new mark does not take its id.
  {
    MBTilesStore other(mission_.path.string());
    Detection again = located;
    again.position.lon += 0.002;
    again.seq = 99;
    other.PutDetection(again);
    Detection more = located;
    more.id = 5;
    more.seq = 100;
    other.PutDetection(more);
    other.Flush();
  }
  registry_->Update(3, {{"note", "seen by the arm camera"}});
  EXPECT_NEAR(Stored().at(3).position.lon, located.position.lon + 0.002, 1e-12);
  EXPECT_EQ(Stored().at(3).note, "seen by the arm camera");
  EXPECT_EQ(registry_->Create(Mark(5, 43, "b"))["id"], 6);
  EXPECT_EQ(Stored().size(), 4u);  // 2, 3, 5, 6
}

}  // namespace
}  // namespace seamap::server
