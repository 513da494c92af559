#include "core/controllers/georef_eval.h"

#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>

#include "core/geo/local_frame.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

// Truth at (0,0) and (10,0); georef's keyframes 1 m east of it, 0.5 m deeper.
class GeorefEvalTest : public ::testing::Test {
 protected:
  GeorefEvalTest() {
    std::ofstream(dir_ / "truth.json") << R"({"origin": {"lat": 43.1, "lon": 131.9}, "submaps": []})";
    std::ofstream(dir_ / "truth.csv") << "time_s,x_m,y_m,depth_m,heading_deg\n0,0,0,10,90\n1,10,0,10,90\n";
    const LocalFrame frame({43.1, 131.9});
    std::ofstream nav(dir_ / "nav.csv");
    nav << "time_s,lat,lon,depth_m,heading_deg,good\n";
    for (int t = 0; t < 2; ++t) {
      const LatLon ll = frame.ToLatLon({10.0 * t + 1, 0});
      char line[128];
      std::snprintf(line, sizeof line, "%d,%.10f,%.10f,10.5,90,%d\n", t, ll.lat, ll.lon, t);
      nav << line;
    }
    options_.nav_path = (dir_ / "nav.csv").string();
    options_.truth_dir = dir_.path().string();
  }

  testing::TempDir dir_;
  GeorefEvalOptions options_;
};

TEST_F(GeorefEvalTest, MeasuresTheKeyframesAgainstTheTruth) {
  const GeorefEvaluation e = EvaluateGeoref(options_);
  EXPECT_EQ(e.figures["keyframes"], 2);
  EXPECT_EQ(e.figures["good_keyframes"], 1);
  EXPECT_NEAR(e.figures["rmse_m"].get<double>(), 1, 1e-3);
  EXPECT_NEAR(e.figures["vertical_rmse_m"].get<double>(), 0.5, 1e-9);
  EXPECT_NEAR(e.figures["heading_rms_deg"].get<double>(), 0, 1e-9);
  EXPECT_EQ(e.text.rfind("keyframes 2 (1 good): horizontal RMSE 1.000 m", 0), 0u) << e.text;
}

TEST_F(GeorefEvalTest, AKeyframeNotInTheTruthIsNamed) {
  std::ofstream(dir_ / "truth.csv") << "time_s,x_m,y_m,depth_m,heading_deg\n0,0,0,10,90\n";
  try {
    EvaluateGeoref(options_);
    FAIL() << "a keyframe without truth was measured";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), options_.nav_path);
    EXPECT_EQ(e.field(), "time_s");
  }
}

}  // namespace
}  // namespace seamap
