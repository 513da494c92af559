#include "core/mosaic/tile_accumulator.h"

#include <gtest/gtest.h>

namespace seamap {
namespace {

// A gray frame covering [x0, x0+w) x [y0, y0+h) with one value and weight.
WarpedFrame Constant(int64_t x0, int64_t y0, int w, int h, uint8_t value, uint8_t weight) {
  WarpedFrame f;
  f.x0 = x0;
  f.y0 = y0;
  f.pixels = cv::Mat(h, w, CV_8UC1, cv::Scalar(value));
  f.weight = cv::Mat(h, w, CV_8UC1, cv::Scalar(weight));
  return f;
}

TEST(TileAccumulator, UntouchedPixelsStayTransparent) {
  TileAccumulator acc(256, 1, 1000, 2000);
  EXPECT_TRUE(acc.Blend(Constant(1000, 2000, 10, 10, 77, 255)));
  cv::Mat t = acc.Finalize();
  ASSERT_EQ(t.type(), CV_8UC2);
  EXPECT_EQ(t.at<cv::Vec2b>(5, 5), cv::Vec2b(77, 255));
  EXPECT_EQ(t.at<cv::Vec2b>(50, 50), cv::Vec2b(0, 0));
}

TEST(TileAccumulator, OverlapIsWeightedMeanNotOverwrite) {
  TileAccumulator acc(256, 1, 0, 0);
  acc.Blend(Constant(0, 0, 100, 100, 100, 255));  // weight 1
  acc.Blend(Constant(0, 0, 100, 100, 200, 85));   // weight 1/3
  // (100*1 + 200/3) / (4/3) = 125
  EXPECT_EQ(acc.Finalize().at<cv::Vec2b>(10, 10)[0], 125);
}

TEST(TileAccumulator, ClipsFramesToTheTile) {
  TileAccumulator acc(256, 1, 256, 256);
  EXPECT_FALSE(acc.Blend(Constant(0, 0, 256, 256, 9, 255)));  // the neighbour tile
  EXPECT_TRUE(acc.Blend(Constant(200, 200, 100, 100, 9, 255)));
  cv::Mat t = acc.Finalize();
  EXPECT_EQ(t.at<cv::Vec2b>(0, 0), cv::Vec2b(9, 255));    // global (256,256)
  EXPECT_EQ(t.at<cv::Vec2b>(43, 43), cv::Vec2b(9, 255));  // global (299,299)
  EXPECT_EQ(t.at<cv::Vec2b>(44, 44), cv::Vec2b(0, 0));
}

TEST(TileAccumulator, SeedFromWrittenTileBlendsInsteadOfOverwriting) {
  cv::Mat written(256, 256, CV_8UC2, cv::Scalar(0, 0));
  written(cv::Rect(0, 0, 128, 256)).setTo(cv::Scalar(60, 255));
  TileAccumulator acc(256, 1, 0, 0);
  acc.Seed(written);
  acc.Blend(Constant(0, 0, 256, 256, 180, 255));
  cv::Mat t = acc.Finalize();
  EXPECT_EQ(t.at<cv::Vec2b>(10, 10)[0], 120);   // old and new averaged
  EXPECT_EQ(t.at<cv::Vec2b>(10, 200)[0], 180);  // only new
}

TEST(TileAccumulator, SeedWithKeptWeightsContinuesAsIfTheTileHadStayed) {
  // A survey line's edge (weight 0.05) under the next line's frame
  // (weight 0.5): read back with its weights, the edge counts as little as
  // it did; read back without them, as one full frame.
  TileAccumulator first(256, 1, 0, 0);
  first.Blend(Constant(0, 0, 256, 256, 40, 13));
  TileAccumulator kept(256, 1, 0, 0), assumed(256, 1, 0, 0), stayed(256, 1, 0, 0);
  stayed.Blend(Constant(0, 0, 256, 256, 40, 13));
  kept.Seed(first.Finalize(), first.Weights());
  assumed.Seed(first.Finalize());
  for (TileAccumulator* acc : {&kept, &assumed, &stayed}) acc->Blend(Constant(0, 0, 256, 256, 200, 128));
  EXPECT_EQ(kept.Finalize().at<cv::Vec2b>(9, 9)[0], stayed.Finalize().at<cv::Vec2b>(9, 9)[0]);
  EXPECT_NEAR(stayed.Finalize().at<cv::Vec2b>(9, 9)[0], (40 * 13 + 200 * 128) / 141.0, 1);
  EXPECT_LT(assumed.Finalize().at<cv::Vec2b>(9, 9)[0], 100);  // the edge dominates: a seam
  EXPECT_EQ(first.Weights().type(), CV_16U);
  EXPECT_EQ(first.Weights().at<uint16_t>(0, 0), 13);  // 13/255 in 1/256 units
}

TEST(TileAccumulator, Colour) {
  TileAccumulator acc(256, 3, 0, 0);
  WarpedFrame f;
  f.pixels = cv::Mat(4, 4, CV_8UC3, cv::Scalar(10, 20, 30));
  f.weight = cv::Mat(4, 4, CV_8UC1, cv::Scalar(255));
  acc.Blend(f);
  cv::Mat t = acc.Finalize();
  ASSERT_EQ(t.type(), CV_8UC4);
  EXPECT_EQ(t.at<cv::Vec4b>(1, 1), cv::Vec4b(10, 20, 30, 255));
}

// Finalize, sixteen pixels at a time, gives every pixel the scalar rule:
// gray sum / weight + 0.5, colour sum * (1 / weight) + 0.5, capped at 255
// and truncated; alpha 255 where a weight arrived, else 0 with colour 0.
TEST(TileAccumulator, FinalizeFollowsTheScalarRuleAtEveryPixel) {
  cv::RNG rng(11);
  for (int channels : {1, 3}) {
    const int size = 256;
    TileAccumulator acc(size, channels, 0, 0);
    cv::Mat sum(size, size, CV_32FC(channels), cv::Scalar::all(0)), weight(size, size, CV_32F, cv::Scalar(0));
    for (int frame = 0; frame < 3; ++frame) {
      WarpedFrame f;
      f.pixels = cv::Mat(size, size, CV_8UC(channels));
      f.weight = cv::Mat(size, size, CV_8U);
      rng.fill(f.pixels, cv::RNG::UNIFORM, 0, 256);
      rng.fill(f.weight, cv::RNG::UNIFORM, 0, 256);
      f.weight(cv::Rect(0, 40 * frame, size, 60)) = 0;  // rows some frames miss
      f.weight.col(17) = 255;                           // and some full weights
      f.weight(cv::Rect(0, 200, size, 10)) = 0;         // rows no frame reaches
      ASSERT_TRUE(acc.Blend(f));
      for (int y = 0; y < size; ++y)  // the same sums, in the same order, as Blend
        for (int x = 0; x < size; ++x) {
          const float k = f.weight.at<uint8_t>(y, x) * (1.0f / 255.0f);
          for (int c = 0; c < channels; ++c)
            sum.ptr<float>(y)[x * channels + c] += k * f.pixels.ptr<uint8_t>(y)[x * channels + c];
          weight.at<float>(y, x) += k;
        }
    }
    const cv::Mat out = acc.Finalize();
    int covered = 0;
    for (int y = 0; y < size; ++y)
      for (int x = 0; x < size; ++x) {
        const float w = weight.at<float>(y, x);
        const uint8_t* d = out.ptr<uint8_t>(y) + x * (channels + 1);
        ASSERT_EQ(d[channels], w > 0 ? 255 : 0) << x << "," << y;
        covered += w > 0;
        for (int c = 0; c < channels; ++c) {
          const float s = sum.ptr<float>(y)[x * channels + c];
          const float value = w <= 0 ? 0.0f : channels == 1 ? s / w + 0.5f : s * (1.0f / w) + 0.5f;
          ASSERT_EQ(d[c], static_cast<uint8_t>(std::min(255.0f, value))) << x << "," << y << " channel " << c;
        }
      }
    EXPECT_GT(covered, size * size / 2);
    EXPECT_LT(covered, size * size);
  }
}

}  // namespace
}  // namespace seamap
