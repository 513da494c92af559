// The detection book: one policy for every writer of the mission's detections,
// and refusals as domain errors (the server maps them to HTTP statuses).
#include "core/mission/detection_book.h"

#include <gtest/gtest.h>

#include "core/mission/mission_metadata.h"
#include "core/tiles/mbtiles_store.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

constexpr double kDegPerMetre = 1.0 / 111319.49;

Detection Found(const std::string& cls, double north_m, const std::string& model, const std::string& source) {
  Detection d;
  d.class_name = cls;
  d.source = source;
  d.model = model;
  d.position = {43.1 + north_m * kDegPerMetre, 5.3};
  d.size_m = std::array<double, 2>{0.8, 0.8};
  return d;
}

DetectionError::Kind KindOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const DetectionError& e) {
    return e.kind();
  }
  ADD_FAILURE() << "no DetectionError";
  return DetectionError::Kind::kInvalid;
}

class DetectionBookTest : public ::testing::Test {
 protected:
  testing::TempDir dir_;
  MBTilesStore store_{(dir_ / "m.mbtiles").string()};
};

TEST_F(DetectionBookTest, RefusalsAreDomainErrorsNamingTheField) {
  DetectionBook book(&store_);
  book.Load(store_);
  try {
    book.Create({{"type", "Feature"}, {"geometry", {{"type", "Point"}, {"coordinates", {5.3, 43.1}}}}});
    ADD_FAILURE() << "a mark without a class was created";
  } catch (const DetectionError& e) {
    EXPECT_EQ(e.kind(), DetectionError::Kind::kInvalid);
    EXPECT_EQ(e.field(), "properties.class");
    EXPECT_EQ(std::string(e.what()), "properties.class: required (what the object is)");
  }
  EXPECT_EQ(KindOf([&] { book.Update(42, {{"note", "x"}}); }), DetectionError::Kind::kNotFound);
  const int64_t id = book.Publish({Found("tyre", 0, "m.onnx#1", "recogniser")}).ids.at(0);
  EXPECT_EQ(KindOf([&] { book.Delete(id); }), DetectionError::Kind::kRefused);
  DetectionBook read_only(nullptr);
  read_only.Load(store_);
  EXPECT_EQ(KindOf([&] { read_only.Delete(id); }), DetectionError::Kind::kRefused);
  try {
    ParseDetectionFilter(std::nullopt, std::nullopt, std::string("high"), std::nullopt);
    ADD_FAILURE() << "a bad min_score passed";
  } catch (const DetectionError& e) {
    EXPECT_EQ(e.field(), "min_score");
    EXPECT_EQ(e.detail(), "expected a number, got 'high'");
  }
}

TEST_F(DetectionBookTest, AnotherVersionOfTheModelFileContinuesAndReplacesItsDetections) {
  DetectionBook book(&store_);
  book.Load(store_);
  PublishOptions first;
  first.replace_model = "m.onnx#1";
  const PublishResult a =
      book.Publish({Found("tyre", 0, "m.onnx#1", "recogniser"), Found("pipe", 5, "m.onnx#1", "recogniser")}, first);
  ASSERT_EQ(a.ids, (std::vector<int64_t>{1, 2}));
  book.Update(1, {{"status", "rejected"}});
  PublishOptions second;
  second.replace_model = "m.onnx#2";  // the same file name: the same model, newer
  const PublishResult b = book.Publish({Found("tyre", 0.05, "m.onnx#2", "recogniser")}, second);
  EXPECT_EQ(b.ids, std::vector<int64_t>{1}) << "continued, not recreated";
  EXPECT_EQ(b.deleted, 1) << "the unreviewed pipe the new version did not find goes";
  EXPECT_EQ(book.Get(1)->status, "rejected");
  EXPECT_EQ(book.Get(1)->model, "m.onnx#2");
  EXPECT_FALSE(book.Get(2));
  // Stereo's object at the same place is another finder's: its own detection, numbered on.
  const PublishResult s = book.Publish({Found("tyre", 0, "m.onnx#2", "stereo")});
  EXPECT_EQ(s.ids, std::vector<int64_t>{3}) << "2 was deleted in this session and is not reused";
  EXPECT_EQ(s.created, 1);
}

TEST_F(DetectionBookTest, PublishFoundIsTheBookForOneCommand) {
  const std::vector<Detection> stored =
      PublishFound(store_, {Found("tyre", 0, "m.onnx#1", "recogniser")}, "m.onnx#1", {"crate", "tyre"});
  ASSERT_EQ(stored.size(), 1u);
  EXPECT_EQ(stored[0].status, "unconfirmed");
  EXPECT_EQ(stored[0].seq, 1);
  const std::vector<Detection> again =
      PublishFound(store_, {Found("tyre", 0.02, "m.onnx#1", "recogniser")}, "m.onnx#1", {"crate", "tyre"});
  EXPECT_EQ(again.at(0).id, stored[0].id);
  EXPECT_EQ(store_.Detections().size(), 1u);
  EXPECT_EQ(ReadMissionMetadata(store_).classes, (std::vector<std::string>{"crate", "tyre"}));
}

}  // namespace
}  // namespace seamap
