#pragma once
// A small simulated survey built once per test binary, shared by the
// integration tests that check the built map.
#include <string>

#include <gtest/gtest.h>

#include "tests/testing/temp_dir.h"

namespace seamap::testing {

struct SimulatedSurvey {
  std::string dir;     // simulate --out
  std::string photo;   // dir/photo
  std::string nav;     // dir/nav.csv
  std::string camera;  // dir/camera.json
  std::string origin = "43.1,131.9";
  // "seamap build" arguments for this survey, without --out.
  std::string BuildArgs() const;
};

// Simulates (once) a survey with `extra` simulate options under a shared temp folder.
const SimulatedSurvey& SharedSurvey(const std::string& name, const std::string& extra);

// 160 frames (16 m, 32 s) over three 6 m lines 0.9 m apart; the navigation
// drifting 0.5 m/min in a fixed direction, with 5 mm and 0.5 degree noise.
const SimulatedSurvey& DriftingSurvey();

// Runs seamap with arguments; returns exit code, output in *out.
int Seamap(const std::string& args, std::string* out);

}  // namespace seamap::testing
