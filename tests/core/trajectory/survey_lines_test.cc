#include "core/trajectory/survey_lines.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace seamap {
namespace {

struct Track {
  std::vector<double> heading_deg;
  std::vector<LocalXY> position;
  std::vector<bool> straight;  // on a line, not in a turn
  void Add(double heading, double east, double north, bool on_line) {
    heading_deg.push_back(heading);
    position.push_back({east, north});
    straight.push_back(on_line);
  }
};

// `lines` passes north/south of `length_m`, `spacing_m` apart towards the east,
// frames every 0.1 m, joined by semicircles sampled every 180 / turn_steps degrees.
Track Lawnmower(int lines, double length_m, double spacing_m, int turn_steps) {
  Track t;
  const int steps = static_cast<int>(std::lround(length_m / 0.1));
  const double r = spacing_m / 2;
  for (int k = 0; k < lines; ++k) {
    const bool north = k % 2 == 0;
    const double x = k * spacing_m;
    for (int i = 0; i <= steps; ++i) t.Add(north ? 0 : 180, x, north ? i * 0.1 : length_m - i * 0.1, true);
    if (k + 1 == lines) break;
    for (int j = 1; j < turn_steps; ++j) {
      const double theta = M_PI * j / turn_steps, deg = 180.0 * j / turn_steps;
      if (north)
        t.Add(deg, x + r - r * std::cos(theta), length_m + r * std::sin(theta), false);
      else
        t.Add(180 - deg, x + r - r * std::cos(theta), -r * std::sin(theta), false);
    }
  }
  return t;
}

TEST(SurveyLines, LawnmowerLinesTakeTheStraightFramesAndTheTurnsBelongToNone) {
  const Track t = Lawnmower(3, 5.0, 0.6, 12);  // turn frames every 15 degrees
  const std::vector<int> line = SegmentLines(t.heading_deg, t.position);
  ASSERT_EQ(line.size(), t.heading_deg.size());
  // Lines 0, 1, 2 in track order; every straight frame on its pass's line.
  int pass = 0;
  for (size_t i = 0; i < line.size(); ++i) {
    if (i > 0 && t.straight[i] && !t.straight[i - 1]) ++pass;
    if (!t.straight[i]) continue;
    EXPECT_EQ(line[i], pass) << "frame " << i;
  }
  // Turn frames: only the first one off each end (15 degrees, within the 20 of
  // the spread) joins the line; the rest of the turn is on no line.
  int turn_on_line = 0, turn_off = 0;
  for (size_t i = 0; i < line.size(); ++i) {
    if (t.straight[i]) continue;
    const double off = std::min(t.heading_deg[i], 180 - t.heading_deg[i]);
    if (off <= 15.0 + 1e-9) {
      EXPECT_NE(line[i], kNoLine) << "frame " << i;
      ++turn_on_line;
    } else {
      EXPECT_EQ(line[i], kNoLine) << "frame " << i;
      ++turn_off;
    }
  }
  EXPECT_EQ(turn_on_line, 4);  // 2 turns x 2 ends
  EXPECT_EQ(turn_off, 2 * 11 - 4);
}

TEST(SurveyLines, HeadingNoiseAndAWildHeadingDoNotSplitAPass) {
  Track t = Lawnmower(3, 5.0, 0.6, 12);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 2.0);
  for (size_t i = 0; i < t.heading_deg.size(); ++i)
    if (t.straight[i]) t.heading_deg[i] = std::fmod(t.heading_deg[i] + noise(rng) + 360, 360);
  t.heading_deg[25] += 60;  // one glitch in the middle of the first pass
  t.heading_deg[26] += 50;  // and its neighbour
  const std::vector<int> line = SegmentLines(t.heading_deg, t.position);
  int most = *std::max_element(line.begin(), line.end());
  EXPECT_EQ(most, 2);
  for (int i = 0; i <= 50; ++i) EXPECT_EQ(line[i], 0) << "frame " << i;
}

TEST(SurveyLines, ASlowCurveIsCutEveryTwentyDegreesAndShortRunsAreTurns) {
  // 12 m of path turning by 60 degrees: at least 3 lines, each within 20 degrees.
  Track t;
  for (int i = 0; i <= 120; ++i) t.Add(0.5 * i, 0, 0.1 * i, true);
  const std::vector<int> line = SegmentLines(t.heading_deg, t.position);
  const int lines = *std::max_element(line.begin(), line.end()) + 1;
  EXPECT_GE(lines, 3);
  for (int k = 0; k < lines; ++k) {
    double lo = 1e9, hi = -1e9;
    for (size_t i = 0; i < line.size(); ++i)
      if (line[i] == k) lo = std::min(lo, t.heading_deg[i]), hi = std::max(hi, t.heading_deg[i]);
    EXPECT_LE(hi - lo, 20.0 + 1e-9) << "line " << k;
  }
  // A straight run of 0.8 m (9 frames) is shorter than a line's 1 m: a turn.
  Track short_track;
  for (int i = 0; i <= 8; ++i) short_track.Add(0, 0, 0.1 * i, true);
  for (int v : SegmentLines(short_track.heading_deg, short_track.position)) EXPECT_EQ(v, kNoLine);
  LineOptions shorter;
  shorter.min_line_length_m = 0.5;
  for (int v : SegmentLines(short_track.heading_deg, short_track.position, shorter)) EXPECT_EQ(v, 0);
}

TEST(SurveyLines, HeadingsAcrossNorthAreOneLine) {
  Track t;
  for (int i = 0; i <= 30; ++i) t.Add(i % 2 ? 355 : 5, 0, 0.1 * i, true);
  for (int v : SegmentLines(t.heading_deg, t.position)) EXPECT_EQ(v, 0);
  EXPECT_TRUE(SegmentLines({}, {}).empty());
}

}  // namespace
}  // namespace seamap
