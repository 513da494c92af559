// Issue 31, fourth pass: where the tether's reach and the fixes' lag trade
// with each other (both only jointly significant), `georef --method tether`
// chooses between reach only, lag only and both by their BIC, and the
// spread of the candidates' maps widens the error estimate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
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

class BuoyModelChoiceTest : public ::testing::Test {
 protected:
  BuoySurveyOptions Options() const {
    BuoySurveyOptions o;
    o.out_dir = (dir_ / "survey").string();
    o.force = true;
    o.cloud_points = 0;
    return o;
  }

  Outcome Run(const BuoySurveyOptions& o) { return ::seamap::testing::GeoreferenceSimulatedBuoySurvey(o); }

  TempDir dir_;
};

TEST_F(BuoyModelChoiceTest, ClockOffsetOnATransectWithACurrentIsNotTakenAsAShorterReach) {
  // Stress survey 33 (scripts/bench_georef.sh stress), GPS draw 1: fixes
  // stamped 2.74 s early and a 0.047 m/s current on a transect. Reach and
  // lag were only jointly significant, the reach (more significant) took
  // the clock offset too and misfitted the U-turn: 0.90 m where 0.28 m was
  // predicted. Chosen by BIC both are kept (0.40 m), and the candidates'
  // disagreement is in the estimate (0.45 m).
  BuoySurveyOptions o = Options();
  o.pattern = "transect";
  o.speed_mps = 0.85;
  o.tether_length_m = 14.4;
  o.depth_m = 3.4;
  o.lines = 2;
  o.line_length_m = 107;
  o.line_spacing_m = 16;
  o.buoy_model = "tractrix";
  o.current_east_mps = 0.0383;
  o.current_north_mps = 0.0267;
  o.clock_offset_s = -2.74;
  o.wave_height_m = 0.12;
  o.gps_sigma_m = 1.17;
  o.gps_rate_hz = 2;
  o.dropout_fraction = 0.07;
  o.gps_outages = 2;
  o.gps_outage_s = 23;
  o.keyframe_interval_s = 1.43;
  o.seed = 33;
  o.gps_seed = 1;
  const Outcome out = Run(o);
  const SubmapGeoref& s = out.submap;
  EXPECT_TRUE(s.lag_estimated);
  EXPECT_LT(s.lag_s, -1);  // the clock offset, at least in part, is a lag
  EXPECT_LT(out.rmse_m, 0.6);
  EXPECT_GT(s.selection_spread_rmse_m, 0.1);
  EXPECT_GE(s.predicted_rmse_m, out.rmse_m / 1.5);
  EXPECT_LE(s.predicted_rmse_m, out.rmse_m / 0.67);
}

TEST_F(BuoyModelChoiceTest, ClockOffsetOnTheIssueSurveyStaysALag) {
  // The bench's clock_offset_3s, seed 1: keeping both reach and lag where
  // they are inseparable put it at 0.389 m (third pass); the BIC keeps the
  // lag alone, and the run stays under 0.3 m.
  BuoySurveyOptions o = Options();
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
  o.clock_offset_s = 3;
  o.seed = 1;
  const Outcome out = Run(o);
  const SubmapGeoref& s = out.submap;
  EXPECT_TRUE(s.lag_estimated);
  EXPECT_NEAR(s.lag_s, 3, 0.5);
  EXPECT_LT(out.rmse_m, 0.3);
}

}  // namespace
}  // namespace seamap
