// Issue 32, the data side end to end: a simulated survey with drums (a class
// the shipped model does not know), built with the recogniser, reviewed
// against its truth (seamap review --truth) and written as training data:
// labels where the truth says, rejected detections as negatives, clear
// refusals for maps with nothing reviewed, unknown files and an existing --out.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/geo/web_mercator.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {
using testing::Seamap;
namespace fs = std::filesystem;

nlohmann::json ReadJson(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

struct Box {
  double x0, y0, x1, y1;
};

// The truth object's footprint bounds in a window's pixels.
Box TruthInWindow(const nlohmann::json& o, int z, int wx, int wy) {
  Box b{1e300, 1e300, -1e300, -1e300};
  for (const auto& p : o["footprint_lonlat"]) {
    const GlobalPixel q = LatLonToPixel({p[1].get<double>(), p[0].get<double>()}, z, 256);
    b.x0 = std::min(b.x0, q.x - wx * 256.0), b.x1 = std::max(b.x1, q.x - wx * 256.0);
    b.y0 = std::min(b.y0, q.y - wy * 256.0), b.y1 = std::max(b.y1, q.y - wy * 256.0);
  }
  return {std::max(b.x0, 0.0), std::max(b.y0, 0.0), std::min(b.x1, 768.0), std::min(b.y1, 768.0)};
}

TEST(TrainingData, AReviewedMissionBecomesLabelsAndNegatives) {
  const std::string model = std::string(SEAMAP_SOURCE_DIR) + "/data/models/seabed_objects.onnx";
  if (!fs::exists(model)) GTEST_SKIP() << "no shipped model at " << model;
  const auto& survey =
      testing::SharedSurvey("training_data", "--objects 4 --object-classes drum,tyre --frames 120 --color --seed 3");
  testing::TempDir dir;
  const std::string map = (dir / "dive.mbtiles").string(), out_dir = (dir / "td").string();
  std::string out;
  ASSERT_EQ(Seamap(survey.BuildArgs() + " --out " + map + " --detect", &out), 0) << out;

  // Nothing reviewed yet: nothing to learn from.
  EXPECT_EQ(Seamap("training-data " + map + " --out " + out_dir, &out), 2) << out;
  EXPECT_NE(out.find("nothing to learn from"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(out_dir)) << "nothing written on a refusal";

  ASSERT_EQ(Seamap("review " + map + " --truth " + survey.dir, &out), 0) << out;
  EXPECT_NE(out.find("against 4 truth objects"), std::string::npos) << out;
  ASSERT_EQ(Seamap("training-data --quiet " + map + " --out " + out_dir, &out), 0) << out;

  const nlohmann::json truth = ReadJson(survey.dir + "/truth/objects.json");
  const nlohmann::json m = ReadJson(fs::path(out_dir) / "manifest.json");
  EXPECT_EQ(m["classes"], nlohmann::json({"tyre", "crate", "pipe", "anchor", "rock", "drum"}));
  ASSERT_EQ(m["missions"].size(), 1u);
  EXPECT_EQ(m["missions"][0]["name"], "dive");
  EXPECT_NE(m["missions"][0]["model"].get<std::string>().find("seabed_objects.onnx#"), std::string::npos);
  EXPECT_GT(m["counts"]["per_class"]["drum"].get<int>(), 0);
  EXPECT_GT(m["counts"]["per_class"]["tyre"].get<int>(), 0);

  // The mission's review, read back: which ids are labels and which negatives.
  std::set<int64_t> rejected, labelled;
  {
    const auto store = OpenExistingMap(map, false);
    for (const Detection& d : store->Records().Detections()) {
      if (d.status == "rejected") rejected.insert(d.id);
      if (d.status == "confirmed") labelled.insert(d.id);
    }
  }
  std::set<int64_t> negatives_seen, labels_seen;
  int labels = 0, windows = 0, empty = 0;
  std::vector<double> errors_px;
  for (const auto& w : m["windows"]) {
    ++windows;
    const int z = w["z"], wx = w["x"], wy = w["y"];
    EXPECT_EQ(w["image"],
              "images/dive_z" + std::to_string(z) + "_x" + std::to_string(wx) + "_y" + std::to_string(wy) + ".png");
    const cv::Mat image = cv::imread((fs::path(out_dir) / w["image"].get<std::string>()).string());
    ASSERT_EQ(image.cols, 768);
    ASSERT_EQ(image.rows, 768);
    std::ifstream label_file(fs::path(out_dir) / w["label"].get<std::string>());
    int lines = 0;
    for (std::string line; std::getline(label_file, line);) {
      std::istringstream s(line);
      int cls = -1;
      double cx, cy, bw, bh;
      ASSERT_TRUE(s >> cls >> cx >> cy >> bw >> bh) << line;
      EXPECT_TRUE(cls == 0 || cls == 5) << line;  // tyres and drums only
      EXPECT_GT(bw, 0);
      EXPECT_LE(cx + bw / 2, 1 + 1e-6);
      ++lines;
    }
    EXPECT_EQ(lines, static_cast<int>(w["labels"].size()));
    empty += w["labels"].empty() && w["negatives"].empty();
    for (const auto& l : w["labels"]) {
      ++labels;
      labels_seen.insert(l["id"].get<int64_t>());
      // The truth object of its class nearest the label, projected into the window.
      double best = 1e300;
      for (const auto& o : truth["objects"]) {
        if (o["class"] != l["class"]) continue;
        const Box t = TruthInWindow(o, z, wx, wy);
        const auto& b = l["box_px"];
        const double err = std::max({std::abs(b[0].get<double>() - t.x0), std::abs(b[1].get<double>() - t.y0),
                                     std::abs(b[2].get<double>() - t.x1), std::abs(b[3].get<double>() - t.y1)});
        best = std::min(best, err);
      }
      // An operator's box is the truth's; a confirmed one the recogniser's, a few px off (z 25: 4 mm a px).
      EXPECT_LT(best, l["source"] == "operator" ? 1.0 : 12.0) << l.dump();
      if (l["source"] == "confirmed") errors_px.push_back(best);
    }
    for (const auto& n : w["negatives"]) {
      EXPECT_TRUE(rejected.count(n["id"].get<int64_t>())) << n.dump();
      negatives_seen.insert(n["id"].get<int64_t>());
    }
  }
  EXPECT_EQ(windows, m["counts"]["windows"].get<int>());
  EXPECT_EQ(labels, m["counts"]["labels"].get<int>());
  EXPECT_EQ(empty, m["counts"]["empty_windows"].get<int>());
  EXPECT_GT(empty, 0);
  EXPECT_EQ(negatives_seen, rejected) << "every rejected detection is a listed negative";
  for (int64_t id : labelled) EXPECT_TRUE(labels_seen.count(id)) << "confirmed " << id << " labelled somewhere";

  // An existing --out needs --overwrite; an unknown file is refused by name.
  EXPECT_EQ(Seamap("training-data " + map + " --out " + out_dir, &out), 2);
  EXPECT_NE(out.find("--overwrite"), std::string::npos) << out;
  EXPECT_EQ(Seamap("training-data --quiet " + map + " --out " + out_dir + " --overwrite", &out), 0) << out;
  EXPECT_EQ(
      Seamap("training-data " + map + " " + (dir / "nope.mbtiles").string() + " --out " + (dir / "td2").string(), &out),
      2);
  EXPECT_NE(out.find("nope.mbtiles"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir / "td2"));
}

}  // namespace
}  // namespace seamap
