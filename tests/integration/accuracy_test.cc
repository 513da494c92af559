// With exact navigation, the base-zoom mosaic must sit where the ground truth
// says: block-wise phase correlation between built tiles and the simulator's
// texture resampled into the same tiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/geo/local_frame.h"
#include "core/geo/web_mercator.h"
#include "core/sim/ground_truth.h"
#include "core/tiles/tile_codec.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::SharedSurvey;

// Offsets (pixels) between built base-zoom blocks and the truth, for a build
// of the shared survey with `origin` as --origin.
std::vector<double> MeasureOffsets(const std::string& origin, const std::string& extra = "") {
  auto survey = SharedSurvey("accuracy", "--frames 60 --line-length 4 --seed 11");
  survey.origin = origin;
  testing::TempDir dir;
  const std::string out = (dir / "m.mbtiles").string();
  std::string log;
  EXPECT_EQ(testing::Seamap(survey.BuildArgs() + " --out " + out + extra, &log), 0) << log;

  GroundTruth truth = GroundTruth::Load(survey.dir);  // georeferenced at 43.1, 131.9
  LocalFrame frame(truth.origin);
  auto store = OpenTileStore(out, "png", false);
  auto meta = store->Metadata();
  const int z = std::stoi(meta.at("maxzoom"));
  const int ts = 256, block = 64;
  std::vector<double> offsets;
  int tiles_checked = 0;
  // Walk the base-zoom tiles over the survey bounds.
  double w, s, e, n;
  if (std::sscanf(meta.at("bounds").c_str(), "%lf,%lf,%lf,%lf", &w, &s, &e, &n) != 4) {
    ADD_FAILURE() << "bad bounds metadata " << meta.at("bounds");
    return {};
  }
  GlobalPixel nw = LatLonToPixel({n, w}, z, ts), se = LatLonToPixel({s, e}, z, ts);
  for (int ty = static_cast<int>(nw.y / ts); ty <= static_cast<int>(se.y / ts); ++ty) {
    for (int tx = static_cast<int>(nw.x / ts); tx <= static_cast<int>(se.x / ts); ++tx) {
      auto bytes = store->GetTile({z, tx, ty});
      if (!bytes) continue;
      cv::Mat tile = DecodeTile(*bytes);
      cv::Mat east(ts, ts, CV_32F), north(ts, ts, CV_32F);
      for (int y = 0; y < ts; ++y)
        for (int x = 0; x < ts; ++x) {
          LatLon ll = PixelToLatLon({double(tx) * ts + x + 0.5, double(ty) * ts + y + 0.5}, z, ts);
          LocalXY p = frame.FromLatLon(ll);
          east.at<float>(y, x) = static_cast<float>(p.east);
          north.at<float>(y, x) = static_cast<float>(p.north);
        }
      cv::Mat expected = RenderTruth(truth, east, north);
      if (expected.channels() > 1) cv::cvtColor(expected, expected, cv::COLOR_BGR2GRAY);
      cv::Mat built, alpha;
      cv::extractChannel(tile, built, 0);
      cv::extractChannel(tile, alpha, tile.channels() - 1);
      ++tiles_checked;
      for (int by = 0; by + block <= ts; by += block)
        for (int bx = 0; bx + block <= ts; bx += block) {
          cv::Rect r(bx, by, block, block);
          if (cv::countNonZero(alpha(r) == 255) < block * block) continue;  // edge of the survey
          cv::Mat a, b, window;
          built(r).convertTo(a, CV_64F);
          expected(r).convertTo(b, CV_64F);
          cv::Scalar sa, sb, da, db;
          cv::meanStdDev(a, sa, da);
          cv::meanStdDev(b, sb, db);
          if (da[0] < 2 || db[0] < 2) continue;  // featureless block: no shift measurable
          cv::createHanningWindow(window, r.size(), CV_64F);
          cv::Point2d shift = cv::phaseCorrelate(a, b, window);
          offsets.push_back(std::hypot(shift.x, shift.y));
        }
    }
  }
  EXPECT_GT(tiles_checked, 4);
  EXPECT_GT(offsets.size(), 30u) << "too few fully covered blocks to judge";
  std::sort(offsets.begin(), offsets.end());
  return offsets;
}

TEST(Accuracy, BaseZoomMosaicMatchesGroundTruth) {
  std::vector<double> offsets = MeasureOffsets("43.1,131.9");
  ASSERT_FALSE(offsets.empty());
  const double median = offsets[offsets.size() / 2];
  const double p90 = offsets[offsets.size() * 9 / 10];
  RecordProperty("median_offset_px", std::to_string(median));
  RecordProperty("p90_offset_px", std::to_string(p90));
  std::printf("accuracy: %zu blocks, median offset %.3f px, p90 %.3f px\n", offsets.size(), median, p90);
  EXPECT_LT(median, 1.0);
  EXPECT_LT(p90, 2.0);
}

TEST(Accuracy, RefiningExactNavigationDoesNotMakeTheMapWorse) {
  // The navigation is exact (to its stated millimetre): refinement from the
  // photos must leave the mosaic within a base pixel of the truth.
  std::vector<double> offsets = MeasureOffsets("43.1,131.9", " --refine-nav --nav-noise 0.001 --nav-drift 0 --quiet");
  ASSERT_FALSE(offsets.empty());
  const double median = offsets[offsets.size() / 2];
  std::printf("accuracy after --refine-nav: %zu blocks, median offset %.3f px\n", offsets.size(), median);
  EXPECT_LT(median, 1.0);
  EXPECT_LT(offsets[offsets.size() * 9 / 10], 2.0);
}

TEST(Accuracy, TheMeasurementSeesAShiftOfTwoPixels) {
  // 1e-7 degrees of longitude at 43.1 N is 8.1 mm: 2.4 pixels at zoom 25.
  std::vector<double> offsets = MeasureOffsets("43.1,131.9000001");
  ASSERT_FALSE(offsets.empty());
  EXPECT_NEAR(offsets[offsets.size() / 2], 2.4, 0.4);
}

}  // namespace
}  // namespace seamap
