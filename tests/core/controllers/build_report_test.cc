#include "core/controllers/build_report.h"

#include <gtest/gtest.h>

namespace seamap {
namespace {

BuildStats Stats() {
  BuildStats s;
  s.frames_seen = 12;
  s.frames_used = 10;
  s.rejections = {{"a.png", 3, "image", "missing image"}, {"b.png", 4, "altitude_m", "frame too large: 9 MB"}};
  s.tiles_written = 52;
  s.tile_bytes = 96 * 1024;
  s.tiles_per_zoom = {{22, 10}, {23, 30}};
  s.seconds = 1.2;
  return s;
}

TEST(BuildReportTest, SummaryCountsFramesReasonsAndTiles) {
  EXPECT_EQ(BuildSummary(Stats()),
            "frames used 10, rejected 2 (1 frame too large, 1 missing image); tiles written 40 (52 writes, 96 KiB); "
            "1.20 s (10.0 frames/s)");
  EXPECT_EQ(BuildSummary(BuildStats{}), "frames used 0, rejected 0; tiles written 0 (0 writes, 0 KiB); 0.00 s");
}

TEST(BuildReportTest, ReportHasTheRunsFiguresAndThePoseReport) {
  MosaicPlan plan;
  plan.base_zoom = 23;
  plan.min_zoom = 22;
  nlohmann::json j = BuildReportJson(Stats(), plan, nullptr, 3);
  EXPECT_EQ(j["frames_seen"], 12);
  EXPECT_EQ(j["frames_rejected"], 2);
  EXPECT_EQ(j["tiles"], 40);
  EXPECT_EQ(j["tiles_per_zoom"]["23"], 30);
  EXPECT_EQ(j["frames_in_map"], 3);
  EXPECT_EQ(j["base_zoom"], 23);
  EXPECT_DOUBLE_EQ(j["frames_per_s"].get<double>(), 10);
  EXPECT_FALSE(j.contains("refine"));
  EXPECT_EQ(BuildReportJson(Stats(), plan, {{"frames", 12}}, 0)["refine"]["frames"], 12);
}

}  // namespace
}  // namespace seamap
