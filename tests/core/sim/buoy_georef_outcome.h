#pragma once
// A simulated buoy survey georeferenced by the tether method, and its
// horizontal error against the simulator's truth: shared by the buoy
// georeferencing tests of tests/core/sim.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/geo/local_frame.h"
#include "core/georef/georef_inputs.h"
#include "core/georef/georeferencer.h"
#include "core/nav/csv_table.h"
#include "core/sim/buoy_survey.h"

namespace seamap::testing {

struct BuoyGeorefOutcome {
  SubmapGeoref submap;
  double rmse_m = 0;  // horizontal, every keyframe against the truth
};

// Simulates the survey `o` (into o.out_dir) and georeferences its first submap.
inline BuoyGeorefOutcome GeoreferenceSimulatedBuoySurvey(const BuoySurveyOptions& o, GeorefOptions options = {}) {
  const BuoySurveySummary summary = SimulateBuoySurvey(o);
  const std::string dir = o.out_dir + "/";
  const BuoyLog log = ReadBuoyLog(dir + "buoy.csv");
  const LocalFrame frame(MedianPosition(log));
  options.tether_length_m = o.tether_length_m;
  options.method = GeorefMethod::kTether;
  const DepthProfile depth = DepthProfile::Samples(ReadDepthLog(dir + "depth.csv").samples);
  BuoyGeorefOutcome out;
  out.submap = GeoreferenceSubmap(summary.keyframe_files.at(0), ReadTumTrajectory(dir + summary.keyframe_files[0]),
                                  MakeBuoyTrack(log, frame), depth, options);
  EXPECT_TRUE(out.submap.fitted) << out.submap.reason;
  const CsvTable truth = ParseCsv(ReadTextLines(dir + "truth.csv"));
  const LocalFrame truth_frame(o.origin);
  double sq = 0;
  for (size_t i = 0; i < out.submap.keyframes.size(); ++i) {
    const auto& k = out.submap.keyframes[i];
    const auto& fields = truth.rows.at(i).fields;
    const LocalXY xy = truth_frame.FromLatLon(frame.ToLatLon({k.position_enu_m.x(), k.position_enu_m.y()}));
    sq += std::pow(xy.east - std::stod(fields[3]), 2) + std::pow(xy.north - std::stod(fields[4]), 2);
  }
  out.rmse_m = std::sqrt(sq / std::max<size_t>(out.submap.keyframes.size(), 1));
  return out;
}

}  // namespace seamap::testing
