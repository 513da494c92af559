#include "core/sim/seabed_texture.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/sim/ground_truth.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(SeabedTextureTest, ProceduralIsDeterministicPerSeed) {
  const cv::Mat a = MakeProceduralTexture({300, 200}, 0.002, false, 8, 5);
  const cv::Mat b = MakeProceduralTexture({300, 200}, 0.002, false, 8, 5);
  const cv::Mat c = MakeProceduralTexture({300, 200}, 0.002, false, 8, 6);
  ASSERT_EQ(a.type(), CV_8UC1);
  ASSERT_EQ(a.size(), cv::Size(300, 200));
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_L1) / a.total(), 5);
}

TEST(SeabedTextureTest, ProceduralHasFeaturesAtEveryScale) {
  const cv::Mat tex = MakeProceduralTexture({1600, 1600}, 0.0015, false, 8, 1);
  cv::Scalar mean, sd;
  cv::meanStdDev(tex, mean, sd);
  EXPECT_NEAR(mean[0], 128, 20);
  EXPECT_GT(sd[0], 25);
  // Detail (Laplacian energy) is strong at every scale: frames sample the
  // texture at about 2x its resolution, tiles overviews at 4x, 8x, 16x...
  for (int factor : {2, 4, 8, 16}) {
    cv::Mat small, lap;
    cv::resize(tex, small, tex.size() / factor, 0, 0, cv::INTER_AREA);
    cv::Laplacian(small, lap, CV_32F);
    cv::meanStdDev(lap, mean, sd);
    EXPECT_GT(sd[0], 8) << "reduction " << factor;
  }
}

TEST(SeabedTextureTest, ColourAndSixteenBitVariants) {
  const cv::Mat color = MakeProceduralTexture({200, 200}, 0.002, true, 8, 1);
  ASSERT_EQ(color.type(), CV_8UC3);
  const cv::Scalar m = cv::mean(color);
  EXPECT_GT(m[2], m[0] + 10);  // sand: more red than blue
  const cv::Mat deep = MakeProceduralTexture({200, 200}, 0.002, false, 16, 1);
  ASSERT_EQ(deep.type(), CV_16UC1);
  const cv::Mat shallow = MakeProceduralTexture({200, 200}, 0.002, false, 8, 1);
  cv::Mat deep8;
  deep.convertTo(deep8, CV_8U, 1 / 257.0);
  EXPECT_LE(cv::norm(deep8, shallow, cv::NORM_INF), 1);
  EXPECT_THROW(MakeProceduralTexture({10, 10}, 0.002, false, 12, 1), InputError);
}

TEST(SeabedTextureTest, LoadsAnImageAndConvertsIt) {
  testing::TempDir dir;
  cv::Mat bgr(20, 30, CV_8UC3, cv::Scalar(10, 100, 200));
  const std::string path = (dir / "t.png").string();
  ASSERT_TRUE(cv::imwrite(path, bgr));
  EXPECT_EQ(LoadTextureImage(path, true, 8).type(), CV_8UC3);
  const cv::Mat gray = LoadTextureImage(path, false, 8);
  EXPECT_EQ(gray.type(), CV_8UC1);
  const cv::Mat deep = LoadTextureImage(path, true, 16);
  EXPECT_EQ(deep.type(), CV_16UC3);
  EXPECT_EQ(deep.at<cv::Vec3w>(0, 0)[2], 200 * 257);
  try {
    LoadTextureImage((dir / "missing.png").string(), false, 8);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--texture");
  }
}

SeabedTexture SavedTexture(int bit_depth, bool color) {
  SeabedTexture t;
  t.image = MakeProceduralTexture({120, 80}, 0.01, color, bit_depth, 3);
  t.res_m = 0.01;
  t.east_min = -0.4;
  t.north_max = 0.3;
  return t;
}

TEST(GroundTruthTest, SaveLoadRoundTripAndSampling) {
  testing::TempDir dir;
  const SeabedTexture t = SavedTexture(8, false);
  SaveTruth(t, {43.1, 131.9}, (dir / "truth").string());
  const GroundTruth g = GroundTruth::Load(dir.path().string());
  EXPECT_EQ(cv::norm(g.image, t.image, cv::NORM_INF), 0);
  EXPECT_EQ(g.res_m, 0.01);
  EXPECT_EQ(g.east_min, -0.4);
  EXPECT_EQ(g.north_max, 0.3);
  EXPECT_EQ(g.origin.lat, 43.1);
  EXPECT_EQ(g.origin.lon, 131.9);

  // Pixel (i, j) centre is at east_min + (i + 0.5) res, north_max - (j + 0.5) res.
  cv::Vec3f v;
  ASSERT_TRUE(g.Sample({-0.4 + 7.5 * 0.01, 0.3 - 3.5 * 0.01}, &v));
  EXPECT_NEAR(v[0], t.image.at<uint8_t>(3, 7), 1e-3);
  EXPECT_EQ(v[0], v[2]);
  // Half way between two pixels: their mean.
  ASSERT_TRUE(g.Sample({-0.4 + 8.0 * 0.01, 0.3 - 3.5 * 0.01}, &v));
  EXPECT_NEAR(v[0], (t.image.at<uint8_t>(3, 7) + t.image.at<uint8_t>(3, 8)) / 2.0, 1e-3);
  EXPECT_FALSE(g.Sample({-0.5, 0}, &v));
  EXPECT_FALSE(g.Sample({0, 0.31}, &v));
}

TEST(GroundTruthTest, SixteenBitColourRoundTrip) {
  testing::TempDir dir;
  const SeabedTexture t = SavedTexture(16, true);
  SaveTruth(t, {-10, 20}, (dir / "truth").string());
  const GroundTruth g = GroundTruth::Load(dir.path().string());
  ASSERT_EQ(g.image.type(), CV_16UC3);
  EXPECT_EQ(cv::norm(g.image, t.image, cv::NORM_INF), 0);
  cv::Vec3f v;
  ASSERT_TRUE(g.Sample({-0.4 + 2.5 * 0.01, 0.3 - 1.5 * 0.01}, &v));
  const cv::Vec3w px = t.image.at<cv::Vec3w>(1, 2);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(v[c], px[c], 1e-2);
}

TEST(GroundTruthTest, RenderTruthSamplesAGridOfLocalPoints) {
  SeabedTexture t = SavedTexture(8, false);
  GroundTruth g;
  g.image = t.image, g.res_m = t.res_m, g.east_min = t.east_min, g.north_max = t.north_max;
  // Pixel centres of the texture itself, in CV_64F and CV_32F: the image back.
  cv::Mat east(80, 120, CV_64F), north(80, 120, CV_64F);
  for (int j = 0; j < 80; ++j)
    for (int i = 0; i < 120; ++i) {
      east.at<double>(j, i) = t.east_min + (i + 0.5) * t.res_m;
      north.at<double>(j, i) = t.north_max - (j + 0.5) * t.res_m;
    }
  cv::Mat out = RenderTruth(g, east, north);
  ASSERT_EQ(out.type(), CV_8UC1);
  EXPECT_EQ(cv::norm(out, t.image, cv::NORM_INF), 0);
  cv::Mat east32, north32;
  east.convertTo(east32, CV_32F);
  north.convertTo(north32, CV_32F);
  out = RenderTruth(g, east32, north32);
  EXPECT_LE(cv::norm(out, t.image, cv::NORM_INF), 1);
  // Outside the texture: 0.
  const cv::Mat far_e(1, 1, CV_64F, cv::Scalar(50.0)), far_n(1, 1, CV_64F, cv::Scalar(0.0));
  EXPECT_EQ(RenderTruth(g, far_e, far_n).at<uint8_t>(0, 0), 0);
}

TEST(GroundTruthTest, LoadNamesTheMissingFile) {
  testing::TempDir dir;
  try {
    GroundTruth::Load(dir.path().string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(e.file().find("texture.json"), std::string::npos);
  }
}

}  // namespace
}  // namespace seamap
