// Issue 31, fifth pass: a current the data do not show is held at zero
// unless the BIC prefers it, and what holding it may cost is in the error
// estimate (docs/GEOREF.md, "Issue 31, fifth pass"). Surveys from the
// randomised stress set (scripts/bench_georef.sh stress), by number.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/geo/local_frame.h"
#include "core/georef/georef_inputs.h"
#include "core/georef/georeferencer.h"
#include "core/nav/csv_table.h"
#include "core/sim/buoy_survey.h"
#include "tests/core/sim/buoy_georef_outcome.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;

using Outcome = ::seamap::testing::BuoyGeorefOutcome;

class BuoyHeldParametersTest : public ::testing::Test {
 protected:
  BuoySurveyOptions Transect() const {
    BuoySurveyOptions o;
    o.out_dir = (dir_ / "survey").string();
    o.force = true;
    o.cloud_points = 0;
    o.pattern = "transect";
    o.lines = 2;
    o.buoy_model = "tractrix";
    return o;
  }

  Outcome Run(const BuoySurveyOptions& o, GeorefOptions options = {}) {
    return ::seamap::testing::GeoreferenceSimulatedBuoySurvey(o, options);
  }

  TempDir dir_;
};

TEST_F(BuoyHeldParametersTest, CurrentNotShownStaysHeldOnATransectWithSagAndClockOffset) {
  // Stress survey 43, GPS draw 1: no current, a 5.9 % sag and fixes
  // stamped 3.32 s early. Freed, a current lowers the cost by only 4.6
  // (2 degrees of freedom) but moves the map 0.77 m, taking up the U-turn's
  // misfit; the map-shift test freed it (0.76 m where 0.28 m was predicted).
  // The BIC keeps it held: 0.06 m.
  BuoySurveyOptions o = Transect();
  o.speed_mps = 0.74;
  o.tether_length_m = 21.4;
  o.depth_m = 7.19;
  o.line_length_m = 189;
  o.line_spacing_m = 20;
  o.tether_sag = 0.059;
  o.clock_offset_s = -3.32;
  o.wave_height_m = 0.13;
  o.gps_sigma_m = 1.32;
  o.gps_rate_hz = 1;
  o.keyframe_interval_s = 1.23;
  o.seed = 43;
  o.gps_seed = 1;
  const Outcome out = Run(o);
  EXPECT_FALSE(out.submap.current_estimated);
  EXPECT_LT(out.rmse_m, 0.2);
  EXPECT_LT(out.submap.predicted_rmse_m, 0.25);
  EXPECT_GT(out.submap.predicted_rmse_m, out.rmse_m);
}

TEST_F(BuoyHeldParametersTest, CurrentThatShowsOnceReachAndLagAreHeldIsFreed) {
  // Stress survey 35, GPS draw 2: a 0.0053 m/s current on a transect with a
  // 45 m tether (a lever of 85 s). Not significant with every parameter
  // free (chi-square 8.2), it lowers the held fit's cost by 19.4, beyond
  // the BIC's 2 ln(2762) = 15.8: freed, 0.11 m; held it would be 0.35 m.
  BuoySurveyOptions o = Transect();
  o.speed_mps = 0.53;
  o.tether_length_m = 45;
  o.depth_m = 14.46;
  o.line_length_m = 170;
  o.line_spacing_m = 21;
  o.current_east_mps = 0.0030;
  o.current_north_mps = -0.0044;
  o.wave_height_m = 0.2;
  o.gps_sigma_m = 1.39;
  o.gps_rate_hz = 2;
  o.multipath_fraction = 0.028;
  o.multipath_m = 22;
  o.gps_outages = 1;
  o.gps_outage_s = 10;
  o.keyframe_interval_s = 2.64;
  o.seed = 35;
  o.gps_seed = 2;
  const Outcome out = Run(o);
  EXPECT_TRUE(out.submap.current_estimated);
  EXPECT_LT(out.rmse_m, 0.2);
  EXPECT_GE(out.submap.predicted_rmse_m, out.rmse_m / 1.5);
}

// A survey's actual over predicted error, each the RMS over its GPS draws
// (the stress bench's criterion): one run's error is one draw of a few
// parameters (docs/GEOREF.md, second pass).
struct DrawsRatio {
  double actual_sq = 0, predicted_sq = 0;
  void Add(const Outcome& out) {
    actual_sq += out.rmse_m * out.rmse_m;
    predicted_sq += out.submap.predicted_rmse_m * out.submap.predicted_rmse_m;
  }
  double ratio() const { return std::sqrt(actual_sq / predicted_sq); }
};

TEST_F(BuoyHeldParametersTest, HeldWeakCurrentIsInTheErrorEstimate) {
  // Stress survey 34: a 0.0058 m/s current across a transect with a 33 m
  // tether, 1.3 standard errors: held at zero, it moves the map by the
  // tether's lever (56 s) as a translation. Predicted 0.19 m for 0.36 m
  // (ratio 1.88) before a quarter of the freed current's variance was added.
  BuoySurveyOptions o = Transect();
  o.speed_mps = 0.59;
  o.tether_length_m = 33.4;
  o.depth_m = 4.74;
  o.line_length_m = 132;
  o.line_spacing_m = 21;
  o.current_east_mps = 0.0021;
  o.current_north_mps = 0.0054;
  o.wave_height_m = 0.14;
  o.gps_sigma_m = 1.88;
  o.gps_rate_hz = 1;
  o.dropout_fraction = 0.1;
  o.keyframe_interval_s = 2.74;
  o.seed = 34;
  DrawsRatio r;
  for (int draw = 1; draw <= 2; ++draw) {
    o.gps_seed = draw;
    const Outcome out = Run(o);
    EXPECT_FALSE(out.submap.current_estimated);
    r.Add(out);
  }
  EXPECT_GE(r.ratio(), 0.67);
  EXPECT_LE(r.ratio(), 1.5);
}

TEST_F(BuoyHeldParametersTest, HeldCurrentAbsentDoesNotMakeTheEstimateTooPessimistic) {
  // Stress survey 7: no current, a transect with a 41 m tether (sag 7 %,
  // fixes 0.5 s early), where the freed current would nearly double the
  // estimate (0.22 -> 0.41 m): with a quarter of it, 0.20 m for 0.28 m.
  BuoySurveyOptions o = Transect();
  o.speed_mps = 0.84;
  o.tether_length_m = 41;
  o.depth_m = 16.27;
  o.line_length_m = 174;
  o.line_spacing_m = 27;
  o.depth_wave_m = 3.18;
  o.depth_period_s = 290;
  o.tether_sag = 0.072;
  o.clock_offset_s = -0.51;
  o.wave_height_m = 0.06;
  o.gps_sigma_m = 1.93;
  o.gps_rate_hz = 1;
  o.dropout_fraction = 0.14;
  o.keyframe_interval_s = 2.86;
  o.seed = 7;
  DrawsRatio r;
  for (int draw = 1; draw <= 2; ++draw) {
    o.gps_seed = draw;
    const Outcome out = Run(o);
    r.Add(out);
  }
  EXPECT_GE(r.ratio(), 0.67);
  EXPECT_LE(r.ratio(), 1.5);
}

TEST_F(BuoyHeldParametersTest, TheBuoysUnknownStartDoesNotPullTheReachOnASpiral) {
  // Independent stress survey 47 (seed base 2000): a tractrix buoy on a
  // 26.3 m tether round a spiral begun in a tight turn, no sag. The model
  // starts the buoy a reach behind along the path's first 2 m, 1.7 m aside
  // of where it was; under GPS noise the settling fixes pulled the reach
  // 3-5 % short and it was freed: 0.80 and 0.88 m, 0.30 m predicted. With
  // the start's trace as noise the reach is held: 0.08-0.11 m.
  BuoySurveyOptions o = Transect();
  o.pattern = "spiral";
  o.speed_mps = 0.6;
  o.tether_length_m = 26.3;
  o.depth_m = 8.11;
  o.lines = 3;
  o.line_length_m = 88;
  o.line_spacing_m = 30;
  o.depth_wave_m = 0.68;
  o.depth_period_s = 127;
  o.wave_height_m = 0.14;
  o.gps_sigma_m = 1.4;
  o.gps_rate_hz = 2;
  o.gps_outages = 2;
  o.gps_outage_s = 29;
  o.keyframe_interval_s = 1.11;
  o.seed = 47;
  // The spiral sees the buoy's offset along the track only to +-1.1 m. Told
  // that clock and tether are as given, the estimate is calibrated; by
  // default it also carries what a 1 s clock offset or a 2 % sag may do,
  // and is pessimistic here, where there is none: no fix can tell
  // (docs/GEOREF.md, "eighth pass").
  GeorefOptions known;
  known.clock_sigma_s = 0;
  known.sag_sigma = 0;
  DrawsRatio r;
  for (int draw = 1; draw <= 2; ++draw) {
    o.gps_seed = draw;
    const Outcome out = Run(o, known);
    EXPECT_NEAR(out.submap.reach_factor, 1, 0.01) << "draw " << draw;
    EXPECT_LT(out.rmse_m, 0.25) << "draw " << draw;
    r.Add(out);
    const Outcome by_default = Run(o);
    EXPECT_EQ(by_default.rmse_m, out.rmse_m) << "draw " << draw;  // the map is the same
    EXPECT_GT(by_default.submap.unseen_offset_rmse_m, 0.2) << "draw " << draw;
    EXPECT_GT(by_default.submap.predicted_rmse_m, out.submap.predicted_rmse_m) << "draw " << draw;
  }
  EXPECT_GE(r.ratio(), 0.67);
  EXPECT_LE(r.ratio(), 1.5);
}

TEST_F(BuoyHeldParametersTest, ACurrentFreedAfterTheSplitsHeldItIsNotCountedTwice) {
  // Independent stress survey 17, GPS draw 1: a lawnmower with a 0.009 m/s
  // current and fixes stamped 2.46 s early. The BICs kept the current held,
  // the map test then freed it, and the selection spread still weighed the
  // held candidates: 0.26 m predicted for 0.06 m. Now 0.10 m.
  BuoySurveyOptions o = Transect();
  o.pattern = "lawnmower";
  o.speed_mps = 0.66;
  o.tether_length_m = 20.4;
  o.depth_m = 5.32;
  o.lines = 3;
  o.line_length_m = 179;
  o.line_spacing_m = 19;
  o.meander_m = 1.38;
  o.meander_wavelength_m = 50;
  o.current_east_mps = 0.0086;
  o.current_north_mps = -0.0009;
  o.clock_offset_s = -2.46;
  o.wave_height_m = 0.08;
  o.gps_sigma_m = 1.23;
  o.gps_rate_hz = 2;
  o.gps_outages = 2;
  o.gps_outage_s = 29;
  o.keyframe_interval_s = 1.05;
  o.seed = 17;
  o.gps_seed = 1;
  const Outcome out = Run(o);
  EXPECT_LT(out.rmse_m, 0.15);
  EXPECT_LT(out.submap.predicted_rmse_m, 2 * std::max(out.rmse_m, 0.05));
  EXPECT_GT(out.submap.predicted_rmse_m, out.rmse_m);
}

TEST_F(BuoyHeldParametersTest, WhereTheOffsetAlongTheTrackIsUnseenWhatItMayBeIsInTheEstimate) {
  // Stress survey 10: a 43.5 m tether round a spiral, fixes stamped 1.56 s
  // late (0.69 m along the track), a 0.038 m/s current. On a spiral the
  // buoy's distance behind is seen only to +-1 m, so reach and lag stay
  // held, and the map is 0.77 and 0.62 m off (two GPS draws). Predicted
  // without the offset: 0.13 m. With what the offset may be given the fit's
  // estimate and the prior of a 1 s clock offset or a 2 % sag, the estimate
  // is calibrated over the two draws.
  BuoySurveyOptions o = Transect();
  o.pattern = "spiral";
  o.speed_mps = 0.44;
  o.tether_length_m = 43.5;
  o.depth_m = 9.72;
  o.lines = 4;
  o.line_length_m = 109;
  o.line_spacing_m = 51;
  o.current_east_mps = -0.0297;
  o.current_north_mps = -0.0235;
  o.clock_offset_s = 1.56;
  o.wave_height_m = 0.12;
  o.gps_sigma_m = 1.6;
  o.gps_rate_hz = 2;
  o.multipath_fraction = 0.026;
  o.multipath_m = 25;
  o.keyframe_interval_s = 2.98;
  o.seed = 10;
  DrawsRatio r;
  for (int draw = 1; draw <= 2; ++draw) {
    o.gps_seed = draw;
    const Outcome out = Run(o);
    ASSERT_FALSE(out.submap.warnings.empty());
    EXPECT_NE(out.submap.warnings.front().find("seen only to"), std::string::npos);
    EXPECT_GT(out.submap.unseen_offset_rmse_m, 0.3) << "draw " << draw;
    EXPECT_GE(out.submap.predicted_rmse_m, out.submap.unseen_offset_rmse_m);
    r.Add(out);
  }
  EXPECT_GE(r.ratio(), 0.67);
  EXPECT_LE(r.ratio(), 1.5);

  // An operator who says the clocks agree and the tether is taut gets
  // nothing added: here that is wrong (fixes 1.56 s late), and the map is
  // 0.77 m off, predicted far less.
  o.gps_seed = 1;
  GeorefOptions known;
  known.clock_sigma_s = 0;
  known.sag_sigma = 0;
  const Outcome held = Run(o, known);
  EXPECT_EQ(held.submap.unseen_offset_rmse_m, 0);
  EXPECT_NEAR(held.submap.reach_factor, 1, 1e-6);
  EXPECT_GT(held.rmse_m, 0.6);
}

}  // namespace
}  // namespace seamap
