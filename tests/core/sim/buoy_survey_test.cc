// The simulated buoy survey and the georeferencing together: exact truth in,
// errors out, for the cases the method must handle and refuse.
#include "core/sim/buoy_survey.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/georef/georef_inputs.h"
#include "core/georef/georeferencer.h"
#include "core/nav/csv_table.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;

struct Outcome {
  std::vector<SubmapGeoref> submaps;
  double rmse_m = 0;       // horizontal, every keyframe against the truth
  double good_rmse_m = 0;  // the good ones
};

class BuoySurveyTest : public ::testing::Test {
 protected:
  BuoySurveyOptions Options() const {
    BuoySurveyOptions o;
    o.out_dir = (dir_ / "survey").string();
    o.force = true;
    o.cloud_points = 10;
    return o;
  }

  Outcome Run(const BuoySurveyOptions& o, GeorefMethod method = GeorefMethod::kUmeyama) {
    const BuoySurveySummary summary = SimulateBuoySurvey(o);
    const std::string dir = o.out_dir + "/";
    const BuoyLog log = ReadBuoyLog(dir + "buoy.csv");
    const LocalFrame frame(MedianPosition(log));
    const BuoyTrack buoy = MakeBuoyTrack(log, frame);
    GeorefOptions options;
    options.tether_length_m = o.tether_length_m;
    options.method = method;
    const DepthProfile depth = o.depth_wave_m != 0 ? DepthProfile::Samples(ReadDepthLog(dir + "depth.csv").samples)
                                                   : DepthProfile::Constant(o.depth_m);
    Outcome out;
    for (const auto& file : summary.keyframe_files)
      out.submaps.push_back(GeoreferenceSubmap(file, ReadTumTrajectory(dir + file), buoy, depth, options));

    // Truth rows are in keyframe order, sub-map after sub-map.
    const CsvTable truth = ParseCsv(ReadTextLines(dir + "truth.csv"));
    const LocalFrame truth_frame(o.origin);
    double sq = 0, good_sq = 0;
    int n = 0, good = 0;
    size_t row = 0;
    for (const auto& s : out.submaps) {
      if (!s.fitted) continue;
      for (const auto& k : s.keyframes) {
        const auto& fields = truth.rows.at(row++).fields;
        EXPECT_NEAR(std::stod(fields[0]), k.time_s, 1e-5);
        const LocalXY xy = truth_frame.FromLatLon(frame.ToLatLon({k.position_enu_m.x(), k.position_enu_m.y()}));
        const double e2 = std::pow(xy.east - std::stod(fields[3]), 2) + std::pow(xy.north - std::stod(fields[4]), 2);
        sq += e2, ++n;
        if (k.good) good_sq += e2, ++good;
      }
    }
    out.rmse_m = n ? std::sqrt(sq / n) : 0;
    out.good_rmse_m = good ? std::sqrt(good_sq / good) : 0;
    return out;
  }

  TempDir dir_;
};

TEST_F(BuoySurveyTest, NoiseFreeSurveyWithinFiveCentimetres) {
  BuoySurveyOptions o = Options();
  o.gps_sigma_m = 0;
  o.slam_noise_m = 0;
  const Outcome out = Run(o);
  ASSERT_EQ(out.submaps.size(), 1u);
  const SubmapGeoref& s = out.submaps[0];
  ASSERT_FALSE(s.degenerate) << s.reason;
  EXPECT_LE(out.rmse_m, 0.05);
  EXPECT_GT(s.good, 200);
  std::ifstream truth(o.out_dir + "/truth.json");
  const double true_scale = nlohmann::json::parse(truth)["submaps"][0]["scale"].get<double>();
  EXPECT_NEAR(s.transform.scale / true_scale, 1.0, 1e-3);
}

TEST_F(BuoySurveyTest, TautSelectionSkipsTurnsAndTheSlackAfterThem) {
  BuoySurveyOptions o = Options();
  o.gps_sigma_m = 0;
  o.slam_noise_m = 0;
  const Outcome out = Run(o);
  const SubmapGeoref& s = out.submaps[0];
  ASSERT_TRUE(s.fitted);
  // The vehicle turns every 200 s + a 39 s turn. The tether stays taut into
  // the first quarter of the turn (the vehicle still draws away from the
  // buoy), then goes slack: the rest of the turn and the first 30 s after
  // it, the buoy left behind on the old line, are never good.
  const double t0 = s.keyframes.front().time_s - 0.5;
  const double leg = 120 / 0.6, turn = M_PI * 7.5 / 0.6;
  for (const auto& k : s.keyframes) {
    const double t = k.time_s - t0;
    if (t > leg + turn + 10 && t < leg + turn + 30) {
      EXPECT_FALSE(k.good) << t << " " << k.reason;
    }
    if (t > leg + turn / 2 && t < leg + turn) {
      EXPECT_FALSE(k.good) << t << " " << k.reason;
    }
  }
  EXPECT_GT(s.rejected.count("turning") ? s.rejected.at("turning") : 0, 100);
  EXPECT_GT(s.rejected.count("slack") ? s.rejected.at("slack") : 0, 50);
}

TEST_F(BuoySurveyTest, WeightedSimilarityBeatsTheTriangleWithNoisyGps) {
  BuoySurveyOptions o = Options();
  o.gps_sigma_m = 1.5;
  o.seed = 3;
  const Outcome umeyama = Run(o);
  const Outcome triangle = Run(o, GeorefMethod::kTriangle);
  ASSERT_TRUE(umeyama.submaps[0].fitted);
  ASSERT_TRUE(triangle.submaps[0].fitted);
  EXPECT_LT(umeyama.rmse_m, 0.5);
  EXPECT_LT(2 * umeyama.rmse_m, triangle.rmse_m);
  // Near the GPS-limited error the fit predicts for itself.
  EXPECT_LT(umeyama.rmse_m, 2.0 * umeyama.submaps[0].predicted_rmse_m);
}

TEST_F(BuoySurveyTest, MultipathFixesAreRejected) {
  BuoySurveyOptions o = Options();
  o.gps_sigma_m = 0.5;
  o.seed = 4;
  const Outcome clean = Run(o);
  o.multipath_fraction = 0.05;
  const Outcome thrown = Run(o);
  ASSERT_TRUE(thrown.submaps[0].fitted);
  EXPECT_GT(thrown.submaps[0].outliers, 0);
  EXPECT_LT(thrown.rmse_m, 1.5 * clean.rmse_m + 0.02);
}

TEST_F(BuoySurveyTest, AClockOffsetShowsAsAlongTrackBias) {
  BuoySurveyOptions o = Options();
  o.gps_sigma_m = 0.3;
  o.clock_offset_s = 5;  // fixes stamped 5 s late: the buoy looks 3 m behind where it was
  const Outcome out = Run(o);
  ASSERT_TRUE(out.submaps[0].fitted);
  EXPECT_NEAR(std::fabs(out.submaps[0].along_track_bias_m), 0.6 * 5, 1.0);
}

TEST_F(BuoySurveyTest, TwoSubMapsEachRecovered) {
  BuoySurveyOptions o = Options();
  o.gps_sigma_m = 0.5;
  o.submaps = 2;
  o.lines = 8;
  const Outcome out = Run(o);
  ASSERT_EQ(out.submaps.size(), 2u);
  for (const auto& s : out.submaps) EXPECT_TRUE(s.fitted && !s.degenerate) << s.reason;
  EXPECT_NE(out.submaps[0].transform.scale, out.submaps[1].transform.scale);
  EXPECT_LT(out.rmse_m, 0.4);
}

TEST_F(BuoySurveyTest, DegenerateSurveysAreRefusedWithTheReason) {
  BuoySurveyOptions o = Options();
  o.gps_sigma_m = 0.5;
  o.pattern = "line";
  o.lines = 3;
  SubmapGeoref line = Run(o).submaps[0];
  EXPECT_TRUE(line.degenerate);
  EXPECT_NE(line.reason.find("straight line"), std::string::npos) << line.reason;

  o.pattern = "hover";
  SubmapGeoref hover = Run(o).submaps[0];
  EXPECT_TRUE(hover.degenerate);
  EXPECT_NE(hover.reason.find("one spot"), std::string::npos) << hover.reason;

  o.pattern = "circles";  // 5 m circles: the buoy (27 m reach) barely moves; with good GPS that shows
  o.gps_sigma_m = 0.1;
  SubmapGeoref circles = Run(o).submaps[0];
  EXPECT_TRUE(circles.degenerate);
  EXPECT_NE(circles.reason.find("too few taut keyframes"), std::string::npos) << circles.reason;
}

// The issue's independent survey: a 355 m lawnmower at 0.66 m/s, 15 m
// tether, depth 5-7 m, 0.1 m waves, 2 Hz GPS at 1.5 m, the buoy running in
// the vehicle's wake (slack in the turns).
BuoySurveyOptions IssueSurvey(BuoySurveyOptions o) {
  o.lines = 4;
  o.line_length_m = 70;
  o.line_spacing_m = 15;
  o.speed_mps = 0.66;
  o.tether_length_m = 15;
  o.depth_m = 6;
  o.depth_wave_m = 1;
  o.depth_period_s = 120;
  o.gps_rate_hz = 2;
  o.gps_sigma_m = 1.5;
  o.keyframe_interval_s = 1.15;
  o.wave_height_m = 0.1;
  o.buoy_model = "path";
  return o;
}

TEST_F(BuoySurveyTest, TetherMethodHoldsWhereTheBuoyRunsInTheWake) {
  BuoySurveyOptions o = IssueSurvey(Options());
  double tether_sq = 0, predicted_sq = 0, umeyama_sq = 0;
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    o.seed = seed;
    const Outcome tether = Run(o, GeorefMethod::kTether);
    const Outcome umeyama = Run(o, GeorefMethod::kUmeyama);
    const Outcome triangle = Run(o, GeorefMethod::kTriangle);
    ASSERT_TRUE(tether.submaps[0].fitted) << tether.submaps[0].reason;
    const SubmapGeoref& s = tether.submaps[0];
    EXPECT_GT(s.wake_share, 0.9) << seed;
    EXPECT_LT(tether.rmse_m, 0.3) << seed;
    EXPECT_LT(tether.rmse_m, triangle.rmse_m) << seed;
    tether_sq += tether.rmse_m * tether.rmse_m;
    umeyama_sq += umeyama.rmse_m * umeyama.rmse_m;
    predicted_sq += s.predicted_rmse_m * s.predicted_rmse_m;
    for (const auto& k : s.keyframes) EXPECT_GT(k.sigma_m, 0);
  }
  // The tractrix model behind --method umeyama misplaces the wake follower.
  EXPECT_GT(umeyama_sq, 4 * tether_sq);
  const double calibration = std::sqrt(tether_sq / predicted_sq);
  EXPECT_GT(calibration, 0.67);
  EXPECT_LT(calibration, 1.5);
}

TEST_F(BuoySurveyTest, TetherMethodNoiseFreeWithinFiveCentimetres) {
  for (const std::string model : {"tractrix", "path"}) {
    BuoySurveyOptions o = IssueSurvey(Options());
    o.buoy_model = model;
    o.gps_sigma_m = 0;
    o.slam_noise_m = 0;
    o.wave_height_m = 0;
    const Outcome out = Run(o, GeorefMethod::kTether);
    ASSERT_TRUE(out.submaps[0].fitted) << out.submaps[0].reason;
    EXPECT_LT(out.rmse_m, 0.05) << model;
  }
  const Outcome base = Run(
      [&] {
        BuoySurveyOptions o = Options();
        o.gps_sigma_m = 0;
        o.slam_noise_m = 0;
        return o;
      }(),
      GeorefMethod::kTether);
  EXPECT_LT(base.rmse_m, 0.05);
}

TEST_F(BuoySurveyTest, TetherMethodMeasuresASaggingTether) {
  // A tractrix buoy 5 % short of the straight tether's reach: the turns tell
  // a shorter reach from a lag, and the reach is measured.
  BuoySurveyOptions o = IssueSurvey(Options());
  o.buoy_model = "tractrix";
  o.tether_sag = 0.05;
  o.seed = 2;
  Outcome out = Run(o, GeorefMethod::kTether);
  ASSERT_TRUE(out.submaps[0].fitted) << out.submaps[0].reason;
  EXPECT_TRUE(out.submaps[0].reach_estimated);
  EXPECT_FALSE(out.submaps[0].lag_estimated);
  EXPECT_NEAR(out.submaps[0].reach_factor, 0.95, 0.015);
  EXPECT_LT(out.rmse_m, 0.3);
  // In the wake a shorter reach and a lag are the same shift along the
  // path: either may take it, and the placement holds.
  o.buoy_model = "path";
  out = Run(o, GeorefMethod::kTether);
  ASSERT_TRUE(out.submaps[0].fitted) << out.submaps[0].reason;
  EXPECT_TRUE(out.submaps[0].reach_estimated || out.submaps[0].lag_estimated);
  EXPECT_LT(out.rmse_m, 0.3);
}

TEST_F(BuoySurveyTest, TetherMethodSeesACurrentInTheTurns) {
  // A current swings the tether off the track (the buoy trails along the
  // vehicle's motion through the water): 0.6 m across the legs for umeyama.
  BuoySurveyOptions o = IssueSurvey(Options());
  o.buoy_model = "tractrix";
  o.current_east_mps = 0.03;
  o.current_north_mps = 0.02;
  o.seed = 2;
  const Outcome out = Run(o, GeorefMethod::kTether);
  ASSERT_TRUE(out.submaps[0].fitted) << out.submaps[0].reason;
  const SubmapGeoref& s = out.submaps[0];
  EXPECT_TRUE(s.current_estimated);
  EXPECT_NEAR(s.current_mps.x(), 0.03, 3 * s.current_sigma_mps.x() + 0.002);
  EXPECT_NEAR(s.current_mps.y(), 0.02, 3 * s.current_sigma_mps.y() + 0.002);
  EXPECT_LT(out.rmse_m, 0.3);
  EXPECT_LT(out.rmse_m, 0.5 * Run(o, GeorefMethod::kUmeyama).rmse_m);

  o.current_east_mps = o.current_north_mps = 0;  // none: kept at zero
  EXPECT_FALSE(Run(o, GeorefMethod::kTether).submaps[0].current_estimated);
}

TEST_F(BuoySurveyTest, TetherMethodMeasuresAClockOffset) {
  BuoySurveyOptions o = Options();
  o.gps_sigma_m = 0.3;
  o.clock_offset_s = 5;  // fixes stamped 5 s late
  const Outcome out = Run(o, GeorefMethod::kTether);
  ASSERT_TRUE(out.submaps[0].fitted) << out.submaps[0].reason;
  EXPECT_TRUE(out.submaps[0].lag_estimated);
  EXPECT_NEAR(out.submaps[0].lag_s, 5, 0.2);
  EXPECT_LT(out.rmse_m, 0.1);
}

TEST_F(BuoySurveyTest, TetherMethodOnASpiralAndWithGpsFaults) {
  BuoySurveyOptions o = IssueSurvey(Options());
  o.buoy_model = "tractrix";
  o.pattern = "spiral";
  o.line_length_m = 100;
  o.line_spacing_m = 20;
  o.seed = 2;
  const Outcome spiral = Run(o, GeorefMethod::kTether);
  ASSERT_TRUE(spiral.submaps[0].fitted) << spiral.submaps[0].reason;
  EXPECT_LT(spiral.rmse_m, 0.3);
  EXPECT_LT(spiral.rmse_m, Run(o, GeorefMethod::kTriangle).rmse_m);

  o = IssueSurvey(Options());
  o.dropout_fraction = 0.1;
  o.multipath_fraction = 0.05;
  o.multipath_m = 15;
  o.gps_outages = 2;
  o.gps_outage_s = 20;
  const Outcome faults = Run(o, GeorefMethod::kTether);
  ASSERT_TRUE(faults.submaps[0].fitted) << faults.submaps[0].reason;
  EXPECT_GT(faults.submaps[0].outliers, 5);
  EXPECT_LT(faults.rmse_m, 0.3);
}

TEST_F(BuoySurveyTest, TetherMethodRefusesDegenerateSurveys) {
  BuoySurveyOptions o = Options();
  o.gps_sigma_m = 0.5;
  o.pattern = "line";
  o.lines = 3;
  const SubmapGeoref line = Run(o, GeorefMethod::kTether).submaps[0];
  EXPECT_TRUE(line.degenerate);
  EXPECT_NE(line.reason.find("straight line"), std::string::npos) << line.reason;

  o.pattern = "hover";
  const SubmapGeoref hover = Run(o, GeorefMethod::kTether).submaps[0];
  EXPECT_TRUE(hover.degenerate);
  EXPECT_NE(hover.reason.find("one spot"), std::string::npos) << hover.reason;

  o.pattern = "circles";
  o.gps_sigma_m = 0.1;
  const SubmapGeoref circles = Run(o, GeorefMethod::kTether).submaps[0];
  EXPECT_TRUE(circles.degenerate);
  EXPECT_NE(circles.reason.find("too few taut keyframes"), std::string::npos) << circles.reason;
}

}  // namespace
}  // namespace seamap
