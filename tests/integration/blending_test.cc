// The handover between consecutive frames against averaging every frame, on
// a survey with navigation noise and lens/light degradations: it covers
// exactly the same seabed and the map comes out sharper.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include <opencv2/imgproc.hpp>

#include "core/tiles/tile_codec.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"

namespace seamap {
namespace {

using testing::Seamap;
using testing::SharedSurvey;

struct Built {
  std::unique_ptr<TileStore> store;
  int base_zoom = 0;
};

Built Build(const testing::TempDir& dir, const std::string& name, const std::string& config,
            const std::string& extra_args = "") {
  const auto& survey = SharedSurvey("blending",
                                    "--frames 120 --line-length 5 --seed 3 --degrade "
                                    "--nav-noise 0.01 --heading-noise 0.5 --image-format jpg");
  const std::string cfg = (dir / (name + ".json")).string(), out = (dir / (name + ".mbtiles")).string();
  std::ofstream(cfg) << config;
  std::string log;
  EXPECT_EQ(Seamap(survey.BuildArgs() + " --config " + cfg + " --out " + out + extra_args, &log), 0) << log;
  Built b;
  b.store = OpenTileStore(out, "png", false);
  b.base_zoom = std::stoi(b.store->Metadata().at("maxzoom"));
  return b;
}

// Mean squared Laplacian of the covered pixels: higher is sharper.
double Sharpness(const cv::Mat& gray_alpha) {
  std::vector<cv::Mat> ch;
  cv::split(gray_alpha, ch);
  cv::Mat lap;
  cv::Laplacian(ch[0], lap, CV_32F);
  cv::Mat inner;
  cv::erode(ch[1], inner, cv::Mat(), {-1, -1}, 2);  // away from the coverage edge
  return cv::mean(lap.mul(lap), inner)[0];
}

TEST(Blending, HandoverCoversWhatAveragingCoversAndIsSharper) {
  testing::TempDir dir;
  Built handover = Build(dir, "handover", R"({"tile_format": "png"})");
  Built averaged = Build(dir, "averaged", R"({"tile_format": "png", "blend_all_overlaps": true})");
  int64_t covered = 0, missing = 0, extra = 0;
  double sharp_handover = 0, sharp_averaged = 0;
  int tiles = 0;
  for (const TileId& id : averaged.store->TileIds()) {
    if (id.z != averaged.base_zoom) continue;
    cv::Mat a = DecodeTile(*averaged.store->GetTile(id));
    auto mine = handover.store->GetTile(id);
    ASSERT_TRUE(mine) << "tile " << id.x << "/" << id.y;
    cv::Mat h = DecodeTile(*mine);
    std::vector<cv::Mat> ca, ch;
    cv::split(a, ca);
    cv::split(h, ch);
    covered += cv::countNonZero(ca[1]);
    missing += cv::countNonZero(ca[1] & ~ch[1]);
    extra += cv::countNonZero(~ca[1] & ch[1]);
    sharp_averaged += Sharpness(a);
    sharp_handover += Sharpness(h);
    ++tiles;
  }
  EXPECT_GT(covered, 500000);
  EXPECT_EQ(missing, 0) << "pixels averaging paints and the handover leaves empty";
  EXPECT_EQ(extra, 0);
  EXPECT_EQ(handover.store->TileIds().size(), averaged.store->TileIds().size());
  // Noisy navigation blurs an average of 10-15 frames; the handover keeps detail.
  EXPECT_GT(sharp_handover, 2 * sharp_averaged) << sharp_handover / tiles << " vs " << sharp_averaged / tiles;
}

}  // namespace
}  // namespace seamap
