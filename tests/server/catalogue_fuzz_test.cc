// Seeded fuzzing of a catalogue's mission records (issue 33): a mission file
// whose frames, track, detections and metadata hold random or hostile values
// must be answered (its records, or an ApiError 404/500 for that mission
// alone), and the mission beside it keeps serving. SEAMAP_FUZZ_SECONDS and
// SEAMAP_FUZZ_SEED as tests/testing/fuzz.h says.
#include <sqlite3.h>

#include <filesystem>

#include <gtest/gtest.h>

#include "server/api_error.h"
#include "server/http/http_util.h"
#include "server/mission_registry.h"
#include "server/photo_preview.h"
#include "tests/server/test_mission.h"
#include "tests/testing/fuzz.h"
#include "tests/testing/temp_dir.h"

namespace seamap::server {
namespace {

struct Column {
  const char* table;
  const char* name;
  const char* json;  // a JSON template of the column ("" for plain values)
};

const std::vector<Column> kColumns = {
    {"frames", "image_path", ""},
    {"frames", "lat", ""},
    {"frames", "lon", ""},
    {"frames", "time_s", ""},
    {"frames", "footprint", "[[5.0,43.0],[5.1,43.0],[5.1,43.1],[5.0,43.1]]"},
    {"frames", "id", ""},
    {"frames", "heading_deg", ""},
    {"track", "lat", ""},
    {"track", "seq", ""},
    {"track", "time_s", ""},
    {"detections", "lat", ""},
    {"detections", "lon", ""},
    {"detections", "score", ""},
    {"detections", "box", "[[5.0,43.0],[5.1,43.1]]"},
    {"detections", "levels", "[20,21]"},
    {"detections", "frames", "[0,1]"},
    {"detections", "seq", ""},
    {"detections", "id", ""},
    {"detections", "time_s", ""},
    {"detections", "class", ""},
    {"detections", "east_m", ""},
    {"detections", "heading_deg", ""},
    {"metadata", "value", ""},
};

void Exec(sqlite3* db, const std::string& sql, const std::string& value, bool as_text) {
  sqlite3_stmt* s = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr), SQLITE_OK) << sql;
  if (as_text) {
    sqlite3_bind_text(s, 1, value.data(), static_cast<int>(value.size()), SQLITE_TRANSIENT);
  } else {
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (end && *end == '\0' && !value.empty())
      sqlite3_bind_double(s, 1, v);
    else
      sqlite3_bind_null(s, 1);
  }
  sqlite3_step(s);  // a constraint may refuse it (a duplicate id): the file stays as it was
  sqlite3_finalize(s);
}

// One to three random damages to the mission's rows.
void Damage(testing::Fuzz& fuzz, const std::filesystem::path& map) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(map.string().c_str(), &db), SQLITE_OK);
  for (size_t n = 1 + fuzz.Below(3); n > 0; --n) {
    const Column& c = fuzz.Pick(kColumns);
    std::string value;
    bool as_text = true;
    switch (fuzz.Below(4)) {
      case 0:
        value = fuzz.HostileNumber();
        as_text = fuzz.OneIn(2);
        break;
      case 1:
        value = fuzz.Bytes(40);
        break;
      case 2:
        value = *c.json ? fuzz.Mutate(c.json) : fuzz.HostileNumber();
        break;
      default:
        value = *c.json ? std::string(c.json).replace(1 + fuzz.Below(4), 3, fuzz.HostileNumber()) : fuzz.Bytes(8);
        break;
    }
    const std::string where =
        std::string(c.table) == "metadata"
            ? " WHERE name IN ('seamap_state','seamap_origin','seamap_t0','format','seamap_layers')"
            : (fuzz.OneIn(2) ? "" : " WHERE rowid = (SELECT min(rowid) FROM " + std::string(c.table) + ")");
    Exec(db, "UPDATE " + std::string(c.table) + " SET " + c.name + " = ?" + where, value, as_text);
  }
  sqlite3_close(db);
}

// Everything a request of the mission's API reads.
void Exercise(const MissionServices& m) {
  nlohmann::json j = m.mission->StatusJson();
  j["classes"] = m.detections->Classes();
  Dump(j);  // as SendJson answers it
  bool more = false;
  Dump(m.detections->QueryPage({}, std::nullopt, 5000, &more));
  m.detections->Pack({}, SIZE_MAX, m.mission->T0());
  for (const auto& p : m.mission->TrackFrom(0)) Dump(TrackPointJson(p));
  for (const auto& f : m.mission->FramesCovering({43.0, 5.0}, 50)) Dump(FrameJson(f));
  if (auto f = m.mission->Frame(0)) {
    std::string problem;
    ResolvePhoto(*f, {m.mission->PhotoFolder(), ""}, &problem);
  }
}

TEST(CatalogueFuzz, HostileMissionRecordsAreAnsweredForThatMissionAlone) {
  testing::TempDir dir;
  const auto folder = dir.path() / "maps";
  const test::TestMission good = test::WriteTestMission(folder);  // "mission"
  const auto base = dir.path() / "base.mbtiles";
  std::filesystem::copy_file(good.path, base);
  testing::Fuzz fuzz;
  int answered = 0, refused = 0;
  while (fuzz.More()) {
    // A new file name each case: a fresh mission for a fresh catalogue.
    const auto hostile = folder / ("hostile" + std::to_string(fuzz.cases()) + ".mbtiles");
    std::filesystem::copy_file(base, hostile);
    Damage(fuzz, hostile);
    MissionRegistry registry(folder.string(), false);
    try {
      Exercise(registry.Services(hostile.stem().string()));
      registry.Follow();
      ++answered;
    } catch (const ApiError& e) {
      EXPECT_TRUE(e.status() == 404 || e.status() == 500) << e.status() << " " << e.what();
      EXPECT_NE(std::string(e.what()).find("mission"), std::string::npos) << e.what();
      ++refused;
    }
    // The other mission is untouched by it.
    const MissionServices m = registry.Services("mission");
    EXPECT_EQ(m.mission->StatusJson()["frames_done"], 4);
    EXPECT_EQ(m.detections->Query({})["features"].size(), 2u);
    std::filesystem::remove(hostile);
  }
  EXPECT_GT(answered + refused, 0);
  std::printf("catalogue fuzz: %d cases, %d answered, %d refused (seed %u)\n", fuzz.cases() - 1, answered, refused,
              fuzz.seed());
}

}  // namespace
}  // namespace seamap::server
