// A recogniser's detections in the registry: what an operator may change
// (status and note), batches published by a recogniser (matched, updated,
// rejected ones never brought back), the class table, filters on status and
// source, and the modem records of what changed.
#include <gtest/gtest.h>

#include "core/mission/mission_classes.h"
#include "core/tiles/modem_record.h"
#include "server/api_error.h"
#include "server/detection_registry.h"
#include "tests/server/test_mission.h"
#include "tests/testing/temp_dir.h"

namespace seamap::server {
namespace {

using nlohmann::json;

std::pair<int, std::string> ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ApiError& e) {
    return {e.status(), e.what()};
  }
  return {0, ""};
}

std::vector<int64_t> Ids(const json& collection) {
  std::vector<int64_t> ids;
  for (const auto& f : collection["features"]) ids.push_back(f["id"].get<int64_t>());
  return ids;
}

// A tyre found 2 m east of the test mission's first recogniser detection.
Detection Found(const std::string& cls, double east_m, double score = 0.7) {
  Detection d;
  d.class_name = cls;
  d.score = score;
  d.position = {43.0002, 5.0002 + east_m / (111319.49 * std::cos(43.0002 * M_PI / 180))};
  d.model = "seamap-tiles.onnx@abcd";
  d.level = 23;
  d.levels = {23, 21};
  d.size_m = std::array<double, 2>{0.6, 0.8};
  d.position_m = std::array<double, 2>{east_m, 22.2};
  d.frames = {1, 0};
  d.frame_id = 1;
  d.box = {{43.0003, 5.0001}, {43.0001, 5.0001}, {43.0001, 5.0003}, {43.0003, 5.0003}, {43.0003, 5.0001}};
  return d;
}

class RecognisedDetections : public ::testing::Test {
 protected:
  void SetUp() override {
    store_ = std::make_unique<MBTilesStore>(mission_.path.string());
    registry_ = std::make_unique<DetectionRegistry>(store_.get(), &events_);
    registry_->Load(*store_);
  }
  std::vector<json> EventsAfter(uint64_t id) {
    std::vector<json> out;
    for (const auto& e : events_.WaitAfter(id, std::chrono::milliseconds(0))) {
      EXPECT_EQ(e.type, "detection");
      out.push_back(json::parse(e.data));
    }
    return out;
  }
  Detection StoredDetection(int64_t id) const {
    MBTilesStore reader(mission_.path.string(), MBTilesStore::Mode::kReadOnly);
    for (const auto& d : reader.Detections())
      if (d.id == id) return d;
    ADD_FAILURE() << "no stored detection " << id;
    return {};
  }

  seamap::testing::TempDir dir_;
  test::TestMission mission_ = test::WriteTestMission(dir_.path());
  EventHub events_;
  std::unique_ptr<MBTilesStore> store_;
  std::unique_ptr<DetectionRegistry> registry_;
};

TEST_F(RecognisedDetections, TheOperatorConfirmsRejectsAndAnnotatesButChangesNothingElse) {
  const json confirmed = registry_->Update(1, {{"status", "confirmed"}, {"note", "checked on the photo"}});
  EXPECT_EQ(confirmed["properties"]["status"], "confirmed");
  EXPECT_EQ(confirmed["properties"]["note"], "checked on the photo");
  EXPECT_EQ(confirmed["properties"]["seq"], 3);
  EXPECT_EQ(StoredDetection(1).status, "confirmed");
  auto events = EventsAfter(0);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0]["action"], "updated");
  EXPECT_EQ(events[0]["feature"]["properties"]["status"], "confirmed");

  // A whole feature echoed back with only the status changed is fine too.
  json feature = *registry_->Get(1);
  feature["properties"]["status"] = "rejected";
  EXPECT_EQ(registry_->Update(1, feature)["properties"]["status"], "rejected");

  for (const json& patch :
       {json{{"class", "rock"}}, json{{"score", 0.1}}, json{{"frames", {3}}},
        json{{"type", "Feature"}, {"geometry", {{"type", "Point"}, {"coordinates", {5.1, 43.1}}}}}}) {
    auto err = ErrorOf([&] { registry_->Update(1, patch); });
    EXPECT_EQ(err.first, 403) << patch.dump();
    EXPECT_NE(err.second.find("only its status and note can be changed"), std::string::npos) << err.second;
  }
  auto err = ErrorOf([&] { registry_->Delete(1); });
  EXPECT_EQ(err.first, 403);
  EXPECT_NE(err.second.find("cannot be deleted, only rejected"), std::string::npos) << err.second;
  err = ErrorOf([&] { registry_->Update(1, {{"status", "maybe"}}); });
  EXPECT_EQ(err.first, 400);
  EXPECT_NE(err.second.find("properties.status"), std::string::npos) << err.second;
  EXPECT_EQ(StoredDetection(1).class_name, "tyre");
  EXPECT_EQ(StoredDetection(1).status, "rejected");
}

TEST_F(RecognisedDetections, OperatorMarksAreConfirmedAndMayBeSetToAnyStatus) {
  const json mark = registry_->Create({{"type", "Feature"},
                                       {"geometry", {{"type", "Point"}, {"coordinates", {5.0, 43.0}}}},
                                       {"properties", {{"class", "wreck"}}}});
  EXPECT_EQ(mark["properties"]["status"], "confirmed");
  EXPECT_EQ(mark["properties"]["source"], "operator");
  EXPECT_EQ(registry_->Update(mark["id"], {{"status", "unconfirmed"}})["properties"]["status"], "unconfirmed");
}

TEST_F(RecognisedDetections, APublishedBatchIsMatchedUpdatedAndNeverBringsARejectedOneBack) {
  PublishOptions options;
  options.model_classes = {"tyre", "crate", "pipe", "anchor", "rock"};
  PublishResult first = registry_->Publish({Found("tyre", 0), Found("crate", 3)}, options);
  EXPECT_EQ(first.created, 2);
  ASSERT_EQ(first.ids.size(), 2u);
  EXPECT_EQ(first.ids[0], 3);  // after the mission's 2
  const int64_t tyre = first.ids[0], crate = first.ids[1];
  const Detection stored = StoredDetection(tyre);
  EXPECT_EQ(stored.source, "recogniser");
  EXPECT_EQ(stored.status, "unconfirmed");
  EXPECT_EQ(stored.levels, (std::vector<int>{23, 21}));
  EXPECT_EQ(stored.frames, (std::vector<int>{1, 0}));
  EXPECT_EQ(EventsAfter(0).size(), 2u);
  // The model's names come first in the class table, then the mission's others.
  EXPECT_EQ(registry_->Classes(), (std::vector<std::string>{"tyre", "anchor", "crate", "pipe", "rock"}));

  registry_->Update(tyre, {{"status", "rejected"}});
  registry_->Update(crate, {{"status", "confirmed"}, {"note", "wooden"}});
  const uint64_t before = events_.LastId();
  // Found again 5 cm away (same object) with a new score, plus the crate unchanged, plus a new pipe.
  PublishResult again = registry_->Publish({Found("tyre", 0.05, 0.9), Found("crate", 3), Found("pipe", 8)}, options);
  EXPECT_EQ(again.ids, (std::vector<int64_t>{tyre, crate, crate + 1}));
  EXPECT_EQ(again.updated, 1);
  EXPECT_EQ(again.unchanged, 1);
  EXPECT_EQ(again.created, 1);
  EXPECT_EQ(StoredDetection(tyre).status, "rejected");  // still rejected, with the new position
  EXPECT_DOUBLE_EQ(StoredDetection(tyre).score, 0.9);
  EXPECT_EQ(StoredDetection(crate).note, "wooden");
  EXPECT_EQ(EventsAfter(before).size(), 2u);  // the unchanged crate is not announced

  // A whole-map search replaces the model's unreviewed detections only.
  PublishOptions replace = options;
  replace.replace_model = "seamap-tiles.onnx@abcd";
  PublishResult redo = registry_->Publish({Found("rock", 20)}, replace);
  EXPECT_EQ(redo.created, 1);
  EXPECT_EQ(redo.deleted, 1);  // the pipe; the rejected tyre and confirmed crate stay
  EXPECT_EQ(Ids(registry_->Query({})), (std::vector<int64_t>{1, 2, tyre, crate, crate + 2}));

  // An operator's mark is never taken over by a recogniser's id.
  Detection clash = Found("anchor", 30);
  clash.id = 2;
  EXPECT_NE(registry_->Publish({clash}).ids[0], 2);
  EXPECT_EQ(StoredDetection(2).source, "operator");
  MBTilesStore reader(mission_.path.string(), MBTilesStore::Mode::kReadOnly);
  EXPECT_EQ(MissionClassTable(reader), registry_->Classes());
  EXPECT_TRUE(MissionT0(reader).has_value());
  EXPECT_TRUE(reader.Metadata().count(kT0Key));
}

TEST_F(RecognisedDetections, FiltersOnStatusAndSource) {
  registry_->Publish({Found("tyre", 0)});
  DetectionFilter f = ParseDetectionFilter(std::nullopt, std::nullopt, std::nullopt, std::nullopt,
                                           std::string("unconfirmed"), std::string("recogniser"));
  EXPECT_EQ(Ids(registry_->Query(f)), (std::vector<int64_t>{1, 3}));
  f = ParseDetectionFilter(std::nullopt, std::nullopt, std::nullopt, std::nullopt, std::string("confirmed"),
                           std::nullopt);
  EXPECT_EQ(Ids(registry_->Query(f)), (std::vector<int64_t>{2}));  // the operator's mark
  f = ParseDetectionFilter(std::nullopt, std::string("tyre"), std::string("0.75"), std::nullopt, std::nullopt,
                           std::string("recogniser,stereo"));
  EXPECT_EQ(Ids(registry_->Query(f)), (std::vector<int64_t>{1}));
  for (auto [status, source, needle] : {std::tuple{"maybe", "", "'status'"}, {"", "robot", "'source'"}}) {
    auto err = ErrorOf([&] {
      ParseDetectionFilter(std::nullopt, std::nullopt, std::nullopt, std::nullopt,
                           *status ? std::optional<std::string>(status) : std::nullopt,
                           *source ? std::optional<std::string>(source) : std::nullopt);
    });
    EXPECT_EQ(err.first, 400);
    EXPECT_NE(err.second.find(needle), std::string::npos) << err.second;
  }
}

TEST_F(RecognisedDetections, PackGivesTheRecordsChangedAfterSinceInSeqOrder) {
  registry_->Publish({Found("tyre", 0), Found("crate", 3)});  // ids 3, 4; seq 3, 4
  registry_->Update(1, {{"status", "confirmed"}});            // seq 5
  const json mark = registry_->Create({{"type", "Feature"},
                                       {"geometry", {{"type", "Point"}, {"coordinates", {5.0, 43.0}}}},
                                       {"properties", {{"class", "wreck"}}}});  // id 5, seq 6
  registry_->Delete(mark["id"]);                                                // seq 7

  auto records = [](const PackedDetections& p) {
    EXPECT_EQ(p.bytes.size(), p.count * kModemRecordBytes);
    std::vector<ModemRecord> out;
    for (size_t i = 0; i < p.bytes.size(); i += kModemRecordBytes)
      out.push_back(DecodeModemRecord(&p.bytes[i], kModemRecordBytes));
    return out;
  };
  DetectionFilter since;
  since.since = 2;
  PackedDetections all = registry_->Pack(since, SIZE_MAX, 100.0);
  EXPECT_EQ(all.last_seq, 7);
  auto r = records(all);
  ASSERT_EQ(r.size(), 4u);  // the deleted mark once, as deleted
  std::vector<int> ids, seqs;
  for (const auto& x : r) {
    ids.push_back(x.id);
    seqs.push_back(x.seq);
  }
  EXPECT_EQ(ids, (std::vector<int>{3, 4, 1, 5}));
  EXPECT_EQ(seqs, (std::vector<int>{3, 4, 5, 7}));
  EXPECT_EQ(r[2].status(), ModemStatus::kConfirmed);
  EXPECT_EQ(r[3].status(), ModemStatus::kDeleted);
  EXPECT_EQ(r[3].source(), ModemSource::kOperator);
  const auto classes = registry_->Classes();
  EXPECT_EQ(classes[r[0].class_id], "tyre");
  EXPECT_EQ(classes[r[3].class_id], "wreck");
  EXPECT_EQ(r[2].time_ds, 0u);   // detection 1 at 12.5 s... minus t0 100 s clamps to 0
  EXPECT_EQ(r[0].size_5cm, 16);  // 0.8 m

  PackedDetections two = registry_->Pack(since, 2, 100.0);
  EXPECT_EQ(records(two).size(), 2u);
  EXPECT_EQ(two.last_seq, 4);  // ask since=4 next
  DetectionFilter crates;
  crates.classes = {"crate"};
  EXPECT_EQ(records(registry_->Pack(crates, SIZE_MAX, std::nullopt)).size(), 1u);
}

}  // namespace
}  // namespace seamap::server
