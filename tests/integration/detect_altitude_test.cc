// The recogniser on a survey flown at 3.5 m (base zoom 24, twice as coarse as
// the surveys the shipped model learnt from): it searches zooms 25 (cut from
// the base tiles, scaled up) and 23, where the objects have their trained
// sizes, and finds them as well as at 2 m; the live search during the build
// (overzoomed windows included) equals seamap detect on the finished map.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <tuple>

#include "core/geo/local_frame.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::Seamap;
namespace fs = std::filesystem;

std::vector<Detection> Recognised(const std::string& map) {
  std::vector<Detection> out;
  for (const Detection& d : OpenExistingMap(map, false)->Records().Detections())
    if (d.source == "recogniser") out.push_back(d);
  std::sort(out.begin(), out.end(), [](const Detection& a, const Detection& b) {
    return std::make_tuple(a.class_name, a.position.lat, a.position.lon) <
           std::make_tuple(b.class_name, b.position.lat, b.position.lon);
  });
  return out;
}

double MetresApart(LatLon a, LatLon b) {
  const LocalXY d = LocalFrame(a).FromLatLon(b);
  return std::hypot(d.east, d.north);
}

TEST(DetectAltitude, ObjectsAreSearchedAtTheirTrainedScaleOnASurveyFlownAt3_5m) {
  const std::string model = std::string(SEAMAP_SOURCE_DIR) + "/data/models/seabed_objects.onnx";
  if (!fs::exists(model)) GTEST_SKIP() << "no shipped model at " << model;
  const auto& survey =
      testing::SharedSurvey("detect_altitude_3_5m", "--objects 10 --seed 5 --altitude-min 3.3 --altitude-max 3.7");
  testing::TempDir dir;
  const std::string map = (dir / "m.mbtiles").string();
  std::string out;
  ASSERT_EQ(Seamap("build " + survey.BuildArgs() + " --out " + map + " --detect", &out), 0) << out;
  EXPECT_NE(out.find("-> zooms 20..24"), std::string::npos) << "the survey's base zoom is 24\n" << out;
  EXPECT_NE(out.find("zooms 25,23"), std::string::npos) << out;
  const std::vector<Detection> found = Recognised(map);

  std::vector<std::pair<std::string, LatLon>> truth;
  std::ifstream in(survey.dir + "/truth/objects.csv");
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string cls, lat, lon;
    std::getline(ss, cls, ',');
    std::getline(ss, lat, ',');
    std::getline(ss, lon, ',');
    truth.push_back({cls, {std::stod(lat), std::stod(lon)}});
  }
  ASSERT_EQ(truth.size(), 10u);
  // Same class within 10 cm, greedy one to one, nearest first. Searched at zooms 24 and 22 (counted down
  // from the base, as before) this survey gave 9 of 10 with 16 detections; the 3.5 m stress survey 0.30 / 0.32.
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t i = 0; i < found.size(); ++i)
    for (size_t k = 0; k < truth.size(); ++k)
      if (found[i].class_name == truth[k].first) {
        const double d = MetresApart(found[i].position, truth[k].second);
        if (d <= 0.10) pairs.emplace_back(d, i, k);
      }
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> used_found(found.size()), used_truth(truth.size());
  size_t matched = 0;
  for (const auto& [d, i, k] : pairs)
    if (!used_found[i] && !used_truth[k]) {
      used_found[i] = used_truth[k] = true;
      ++matched;
    }
  EXPECT_GE(matched, 9u) << found.size() << " detections\n" << out;
  EXPECT_GE(static_cast<double>(matched) / std::max<size_t>(found.size(), 1), 0.9) << "precision\n" << out;

  // The finished map searched again: the same objects.
  ASSERT_EQ(Seamap("detect --quiet " + map, &out), 0) << out;
  const std::vector<Detection> offline = Recognised(map);
  ASSERT_EQ(offline.size(), found.size());
  for (size_t i = 0; i < found.size(); ++i) {
    EXPECT_EQ(offline[i].class_name, found[i].class_name);
    EXPECT_LT(MetresApart(offline[i].position, found[i].position), 0.001);
  }
}

}  // namespace
}  // namespace seamap
