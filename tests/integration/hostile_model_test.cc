// Issue 33 (rows 2, 3, 5, 10, 14: models and what they find), end to end: a
// model OpenCV would crash on, inf/NaN boxes, a model that proposes
// everything, a min score that is no probability, hostile class names and
// classes files. Each is a clear error (exit 2 naming the model, field or
// option) or a correct result; no map is left unreadable. The models are
// built by the test (tests/testing/onnx_builder.h).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <regex>

#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/onnx_builder.h"

namespace seamap {
namespace {

using testing::OnnxModelBytes;
using testing::Seamap;
namespace fs = std::filesystem;

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
const std::map<std::string, std::string> kNames = {{"names", R"(["tyre", "crate"])"}};

const testing::SimulatedSurvey& Survey() {
  return testing::SharedSurvey("hostile_model", "--frames 40 --line-length 3 --seed 3");
}

// Two boxes every window: a tyre and a crate.
testing::OnnxModelSpec TwoBoxes(const std::map<std::string, std::string>& metadata = kNames) {
  return testing::PlantedYoloModel(
      {1, 6, 2}, testing::V8Values({{20, 24, 10, 8, 0.1f, 0.8f}, {44, 40, 12, 12, 0.9f, 0.2f}}), metadata);
}

std::string WriteModel(const testing::TempDir& dir, const std::string& name, const testing::OnnxModelSpec& spec) {
  return testing::WriteFile(dir / name, OnnxModelBytes(spec)).string();
}

std::string BuildMap(const testing::TempDir& dir) {
  const std::string map = (dir / "m.mbtiles").string();
  std::string out;
  EXPECT_EQ(Seamap(Survey().BuildArgs() + " --out " + map, &out), 0) << out;
  return map;
}

size_t Recognised(const std::string& map) {
  size_t n = 0;
  for (const Detection& d : OpenExistingMap(map, false)->Records().Detections()) n += d.source == "recogniser";
  return n;
}

void ExpectRefused(const std::string& args, const std::vector<std::string>& said, std::string* out_copy = nullptr) {
  std::string out;
  EXPECT_EQ(Seamap(args, &out), 2) << args.substr(0, 300) << "\n" << out.substr(0, 2000);
  for (const std::string& s : said) EXPECT_NE(out.find(s), std::string::npos) << s << "\n" << out.substr(0, 2000);
  EXPECT_LT(out.size(), 1000u) << "a long input echoed: " << out.substr(0, 300);
  if (out_copy) *out_copy = out;
}

// Row 2: OpenCV crashed (SIGSEGV) on these in detect, build --detect and replay --detect.
TEST(HostileModel, ModelsOpenCvWouldCrashOnAreRefusedNamingTheModel) {
  testing::TempDir dir;
  const std::string map = BuildMap(dir);
  testing::OnnxModelSpec big = TwoBoxes();
  big.initializers[0] = testing::FloatTensor("w", {100000000}, std::vector<float>(36864, 0.0f));  // 147 KB
  const std::string big_model = WriteModel(dir, "big_initializer.onnx", big);
  testing::OnnxModelSpec bare = TwoBoxes();
  bare.initializers.clear();
  const std::string bare_model = WriteModel(dir, "no_initializers.onnx", bare);

  ExpectRefused("detect --quiet " + map + " --model " + big_model,
                {"big_initializer.onnx", "initializer 0 (w)", "100000000 elements", "147456 bytes"});
  ExpectRefused("detect --quiet " + map + " --model " + bare_model, {"no_initializers.onnx", "input 'w'"});
  EXPECT_EQ(Recognised(map), 0u);
  const std::string built = (dir / "b.mbtiles").string();
  ExpectRefused(Survey().BuildArgs() + " --out " + built + " --detect --detect-model " + big_model,
                {"big_initializer.onnx", "initializer 0 (w)"});
  EXPECT_FALSE(fs::exists(built));
  const std::string replayed = (dir / "r.mbtiles").string();
  ExpectRefused("replay " + Survey().dir + " --out " + replayed +
                    " --speed max --host 127.0.0.1 --port 0 --quiet --exit-when-done --detect --detect-model " +
                    bare_model,
                {"no_initializers.onnx", "input 'w'"});
  EXPECT_FALSE(fs::exists(replayed));
}

// Row 3: inf/NaN boxes are dropped and counted; a record stored with them by
// an older recogniser is left out of export and detections-pack, said.
TEST(HostileModel, NonFiniteBoxesAreDroppedAndStoredOnesDoNotFailTheMap) {
  testing::TempDir dir;
  const std::string map = BuildMap(dir);
  const std::string model = WriteModel(dir, "nan_boxes.onnx",
                                       testing::PlantedYoloModel({1, 6, 5},
                                                                 testing::V8Values({{20, 24, 10, 8, 0.1f, 0.8f},
                                                                                    {44, 40, 12, 12, 0.9f, 0.2f},
                                                                                    {kInf, 24, 10, 8, 0.9f, 0.1f},
                                                                                    {30, kNaN, 10, 8, 0.1f, 0.9f},
                                                                                    {30, 30, 10, 8, kNaN, 0.9f}}),
                                                                 kNames));
  std::string out;
  ASSERT_EQ(Seamap("detect --quiet " + map + " --model " + model, &out), 0) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex("(\\d+) windows searched"))) << out;
  const int windows = std::stoi(m[1]);
  ASSERT_GT(windows, 0);
  EXPECT_NE(out.find(std::to_string(3 * windows) + " boxes with an inf/NaN coordinate or score dropped"),
            std::string::npos)
      << out;
  ASSERT_GT(Recognised(map), 0u);
  for (const Detection& d : OpenExistingMap(map, false)->Records().Detections()) {
    EXPECT_TRUE(std::isfinite(d.position.lat) && std::isfinite(d.position.lon)) << d.id;
    for (const LatLon& c : d.box) EXPECT_TRUE(std::isfinite(c.lat) && std::isfinite(c.lon)) << d.id;
  }
  const std::string pack = (dir / "all.bin").string();
  ASSERT_EQ(Seamap("detections-pack " + map + " --out " + pack, &out), 0) << out;
  const size_t good = Recognised(map);
  EXPECT_EQ(fs::file_size(pack), 24 * good);

  // A record as the recogniser stored it before: a NaN box and position (SQLite keeps NULLs).
  int64_t bad_id = 0;
  {
    auto store = OpenExistingMap(map, true);
    Detection d = store->Records().Detections().back();
    bad_id = d.id = d.id + 100;
    d.position = {std::nan(""), std::nan("")};
    for (LatLon& c : d.box) c = {std::nan(""), std::nan("")};
    d.position_m = std::array<double, 2>{kInf, kInf};
    store->Records().PutDetection(d);
    store->Flush();
  }
  ASSERT_EQ(Seamap("detections-pack " + map + " --out " + pack, &out), 0) << out;
  EXPECT_NE(out.find("1 detections with non-finite or unreadable numbers left out (ids " + std::to_string(bad_id)),
            std::string::npos)
      << out;
  EXPECT_EQ(fs::file_size(pack), 24 * good);
  const std::string copy = (dir / "copy.mbtiles").string();
  ASSERT_EQ(Seamap("export --quiet " + map + " " + copy, &out), 0) << out;
  EXPECT_NE(out.find("1 detections with non-finite or unreadable numbers not exported"), std::string::npos) << out;
  EXPECT_EQ(Recognised(copy), good);
  ASSERT_EQ(Seamap("export --quiet " + map + " " + (dir / "m.pmtiles").string(), &out), 0) << out;
  EXPECT_NE(out.find("1 detections with non-finite or unreadable numbers not exported"), std::string::npos) << out;
}

// Row 5: a model that proposes thousands of boxes a window at the lowest
// score: each window keeps its best 300, said; scores that are no probability refused.
TEST(HostileModel, ProposalsAreCappedPerWindowAndTheScoreHasAFloor) {
  testing::TempDir dir;
  const std::string map = BuildMap(dir);
  std::vector<std::vector<float>> rows;
  for (int i = 0; i < 6400; ++i)  // an 80 x 80 grid of boxes that do not overlap
    rows.push_back({0.4f + (i % 80) * 0.8f, 0.4f + (i / 80) * 0.8f, 0.4f, 0.4f, 0.01f + 0.9f * (i % 97) / 97, 0.005f});
  const std::string model =
      WriteModel(dir, "everything.onnx", testing::PlantedYoloModel({1, 6, 6400}, testing::V8Values(rows), kNames));
  std::string out;
  ASSERT_EQ(Seamap("detect --quiet " + map + " --model " + model + " --min-score 0.001", &out), 0) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex("(\\d+) windows searched"))) << out;
  const size_t windows = std::stoul(m[1]);
  EXPECT_NE(out.find("windows proposed more boxes than 3000 before NMS or 300 after it"), std::string::npos) << out;
  EXPECT_LE(Recognised(map), 300 * windows);
  EXPECT_GT(Recognised(map), 0u);

  for (const char* score : {"0", "1e-300", "0.0009", "1.5"})
    ExpectRefused("detect --quiet " + map + " --model " + model + " --min-score " + score, {"--min-score", "0.001"});
  ExpectRefused(Survey().BuildArgs() + " --out " + (dir / "b.mbtiles").string() + " --detect --detect-model " +
                    WriteModel(dir, "tiny_score.onnx",
                               TwoBoxes({{"names", R"(["tyre", "crate"])"}, {"seamap.min_score", "1e-300"}})),
                {"tiny_score.onnx", "seamap.min_score"});
  // A 10 MB value is quoted, not echoed (ExpectRefused: under 1000 characters).
  ExpectRefused(
      "detect --quiet " + map + " --model " +
          WriteModel(dir, "long_score.onnx",
                     TwoBoxes({{"names", R"(["tyre", "crate"])"}, {"seamap.min_score", std::string(10 << 20, '7')}})),
      {"long_score.onnx", "seamap.min_score", "(10485760 bytes)"});
}

// Rows 10 and 14: classes files that are no file, huge ids and empty names.
TEST(HostileModel, HostileClassNamesAreRefusedNamingTheField) {
  testing::TempDir dir;
  const std::string map = BuildMap(dir);
  const std::string model = WriteModel(dir, "two.onnx", TwoBoxes());
  ExpectRefused("detect --quiet " + map + " --model " + model + " --classes /dev/zero",
                {"/dev/zero", "--classes", "not a regular file"});
  const std::string big = testing::WriteFile(dir / "big.txt", std::string(2 << 20, 'a')).string();
  ExpectRefused("detect --quiet " + map + " --model " + model + " --classes " + big,
                {"big.txt", "--classes", "1048576"});
  ExpectRefused("detect --quiet " + map + " --model " +
                    WriteModel(dir, "huge_id.onnx", TwoBoxes({{"names", "{0: 'tyre', 99999999999999: 'crate'}"}})),
                {"huge_id.onnx", "'names'", "99999999999999", "too large"});
  ExpectRefused(
      "detect --quiet " + map + " --model " + WriteModel(dir, "empty_names.onnx", TwoBoxes({{"names", R"(["", ""])"}})),
      {"empty_names.onnx", "'names'", "empty name"});
  ExpectRefused("detect --quiet " + map + " --model /dev/zero", {"/dev/zero", "not a regular file"});
  EXPECT_EQ(Recognised(map), 0u);
}

}  // namespace
}  // namespace seamap
