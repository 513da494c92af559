// Recogniser detections through a real `seamap serve` on loopback: the
// operator's review (status and note only), the JSON and the 24-byte modem
// records of /api/detections.bin agreeing detection for detection, and
// `seamap detections-pack` writing the same bytes and decoding them.
#include <httplib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/mission/mission_classes.h"
#include "core/tiles/mbtiles_store.h"
#include "core/tiles/modem_record.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/child_process.h"

namespace seamap::testing {
namespace {
using nlohmann::json;
using std::chrono::seconds;

const std::string kWeb = std::string(SEAMAP_SOURCE_DIR) + "/web";

// Three recognised objects on the mission's first frames and one operator mark.
void SeedDetections(const std::string& mission) {
  MBTilesStore store(mission);
  const auto frames = store.Frames();
  ASSERT_GE(frames.size(), 6u);
  const char* classes[] = {"tyre", "crate", "tyre"};
  const double scores[] = {0.91, 0.55, 0.42};
  for (int i = 0; i < 3; ++i) {
    const FrameRecord& f = frames[2 * i + 1];
    Detection d;
    d.id = i + 1;
    d.seq = i + 1;
    d.class_name = classes[i];
    d.score = scores[i];
    d.source = "recogniser";
    d.status = "unconfirmed";
    d.model = "seamap-tiles.onnx@0011aabb";
    d.position = {(f.footprint[0].lat + f.footprint[2].lat) / 2, (f.footprint[0].lon + f.footprint[2].lon) / 2};
    d.size_m = std::array<double, 2>{0.4 + 0.3 * i, 0.5};
    d.level = 25;
    d.levels = {25, 23};
    d.frames = {f.id, f.id + 1};
    d.frame_id = f.id;
    d.time_s = f.time_s;
    d.created = d.updated = "2026-11-25T10:00:00Z";
    store.PutDetection(d);
  }
  Detection mark;
  mark.id = 4;
  mark.seq = 4;
  mark.class_name = "wreck";
  mark.position = frames[0].position;
  mark.source = "operator";
  store.PutDetection(mark);
  StoreClassTable(&store, {"tyre", "crate", "pipe", "anchor", "rock"});
  store.Flush();
}

std::vector<ModemRecord> Decode(const std::string& bytes) {
  std::vector<ModemRecord> out;
  for (size_t i = 0; i + kModemRecordBytes <= bytes.size(); i += kModemRecordBytes)
    out.push_back(DecodeModemRecord(reinterpret_cast<const uint8_t*>(bytes.data() + i), kModemRecordBytes));
  return out;
}

TEST(DetectionsPack, TheBinaryRecordsAreTheJsonDetectionsAndTheCliWritesTheSameBytes) {
  const SimulatedSurvey& survey = SharedSurvey("serve", "--frames 40");
  TempDir tmp;
  const std::string mission = (tmp / "m.mbtiles").string();
  std::string out;
  ASSERT_EQ(Seamap(survey.BuildArgs() + " --quiet --out " + mission, &out), 0) << out;
  SeedDetections(mission);
  if (HasFatalFailure()) return;

  std::string served_bin;
  {
    ChildProcess serve(
        {SeamapBinary(), "serve", mission, "--host", "127.0.0.1", "--port", "0", "--web", kWeb, "--token", "secret"});
    auto line = serve.WaitForLine("serving http://", seconds(30));
    ASSERT_TRUE(line) << serve.output();
    httplib::Client api("127.0.0.1", PortFromServingLine(*line));
    const httplib::Headers auth = {{"Authorization", "Bearer secret"}};

    auto status = api.Get("/api/status");
    ASSERT_TRUE(status && status->status == 200);
    const json st = json::parse(status->body);
    EXPECT_EQ(st["classes"], json({"tyre", "crate", "pipe", "anchor", "rock", "wreck"}));
    MBTilesStore reader(mission, MBTilesStore::Mode::kReadOnly);
    ASSERT_TRUE(st["t0"].is_number());
    EXPECT_DOUBLE_EQ(st["t0"].get<double>(), *reader.Frames()[0].time_s);
    const double t0 = st["t0"].get<double>();

    // The operator reviews: status and note change, nothing else, no delete.
    auto ok = api.Patch("/api/detections/2", auth, R"({"status":"confirmed","note":"planks"})", "application/json");
    ASSERT_TRUE(ok);
    EXPECT_EQ(ok->status, 200) << ok->body;
    auto moved = api.Patch("/api/detections/2", auth, R"({"class":"pipe"})", "application/json");
    ASSERT_TRUE(moved);
    EXPECT_EQ(moved->status, 403);
    EXPECT_NE(moved->body.find("only its status and note"), std::string::npos) << moved->body;
    auto gone = api.Delete("/api/detections/1", auth);
    ASSERT_TRUE(gone);
    EXPECT_EQ(gone->status, 403);

    auto tyres = api.Get("/api/detections?class=tyre&min_score=0.6");
    ASSERT_TRUE(tyres && tyres->status == 200);
    const json tyres_json = json::parse(tyres->body);
    ASSERT_EQ(tyres_json["features"].size(), 1u);
    EXPECT_EQ(tyres_json["features"][0]["id"], 1);
    auto confirmed = api.Get("/api/detections?status=confirmed&source=recogniser");
    ASSERT_TRUE(confirmed);
    EXPECT_EQ(json::parse(confirmed->body)["features"].size(), 1u);

    auto all = api.Get("/api/detections");
    auto bin = api.Get("/api/detections.bin");
    ASSERT_TRUE(all && bin);
    ASSERT_EQ(bin->status, 200) << bin->body;
    EXPECT_EQ(bin->get_header_value("Content-Type"), "application/octet-stream");
    ASSERT_EQ(bin->body.size() % kModemRecordBytes, 0u);
    const json features = json::parse(all->body)["features"];
    const auto records = Decode(bin->body);
    ASSERT_EQ(records.size(), features.size());
    EXPECT_EQ(bin->get_header_value("X-SeaMap-Last-Seq"),
              std::to_string(json::parse(all->body)["last_seq"].get<int>()));
    std::map<int, json> by_id;
    for (const json& f : features) by_id[f["id"].get<int>()] = f;
    int last_seq = 0;
    for (const ModemRecord& r : records) {
      ASSERT_TRUE(by_id.count(r.id)) << r.id;
      const json& f = by_id[r.id];
      const json& p = f["properties"];
      EXPECT_GT(r.seq, last_seq);  // seq order
      last_seq = r.seq;
      EXPECT_EQ(r.seq, p["seq"].get<int>());
      EXPECT_NEAR(r.lon(), f["geometry"]["coordinates"][0].get<double>(), 0.5e-7 + 1e-12);
      EXPECT_NEAR(r.lat(), f["geometry"]["coordinates"][1].get<double>(), 0.5e-7 + 1e-12);
      EXPECT_EQ(st["classes"][r.class_id], p["class"]);
      EXPECT_EQ(r.score_pct, std::lround(p["score"].get<double>() * 100));
      const char* statuses[] = {"unconfirmed", "confirmed", "rejected", "deleted"};
      EXPECT_EQ(statuses[static_cast<int>(r.status())], p["status"]);
      EXPECT_EQ(r.source() == ModemSource::kOperator, p["source"] == "operator");
      if (p["time_s"].is_number())
        EXPECT_NEAR(r.time_ds / 10.0, p["time_s"].get<double>() - t0, 0.05 + 1e-9);
      else
        EXPECT_EQ(r.time_ds, kModemUnknownTime);
    }
    EXPECT_EQ(records.back().id, 2);  // the confirmed crate changed last

    auto since = api.Get("/api/detections.bin?since=4");
    ASSERT_TRUE(since);
    ASSERT_EQ(Decode(since->body).size(), 1u);
    EXPECT_EQ(Decode(since->body)[0].status(), ModemStatus::kConfirmed);
    auto two = api.Get("/api/detections.bin?max=2&class=tyre,crate,wreck");
    ASSERT_TRUE(two);
    EXPECT_EQ(two->body.size(), 2 * kModemRecordBytes);
    EXPECT_EQ(two->get_header_value("X-SeaMap-Last-Seq"), "3");  // seqs 1 and 3 (2 was changed again: 5)
    auto bad = api.Get("/api/detections.bin?max=lots");
    ASSERT_TRUE(bad);
    EXPECT_EQ(bad->status, 400);
    EXPECT_NE(bad->body.find("'max'"), std::string::npos) << bad->body;
    served_bin = bin->body;
  }

  const std::string file = (tmp / "d.bin").string();
  ASSERT_EQ(Seamap("detections-pack " + mission + " --out " + file, &out), 0) << out;
  std::ifstream in(file, std::ios::binary);
  const std::string packed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(packed, served_bin);
  ASSERT_EQ(Seamap("detections-pack --decode " + file + " --map " + mission, &out), 0) << out;
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1 + static_cast<long>(served_bin.size() / kModemRecordBytes));
  EXPECT_NE(out.find("1,1,crate,2,5,"), std::string::npos) << out;  // version, class id, class, id, seq
  std::ofstream(file, std::ios::binary | std::ios::app) << "x";
  EXPECT_EQ(Seamap("detections-pack --decode " + file, &out), 2);
  EXPECT_NE(out.find("not a whole number of 24-byte records"), std::string::npos) << out;
}

}  // namespace
}  // namespace seamap::testing
