#include "core/mosaic/blend_rule.h"

#include <gtest/gtest.h>

#include <cmath>

namespace seamap {
namespace {

const ImageShape kShape(CameraFromFocalLength(8, 12.9, 200, 100));

TEST(BlendRule, TheTentIsOneAtTheCentreAndZeroAtTheEdges) {
  const FeatherCurve linear(1.0);
  EXPECT_NEAR(BlendWeight(kShape, linear, 99.5f, 49.5f, nullptr, 0), 1.0f, 1e-6f);
  EXPECT_NEAR(BlendWeight(kShape, linear, -0.5f, 49.5f, nullptr, 0), 0.0f, 1e-6f);
  EXPECT_NEAR(BlendWeight(kShape, linear, 99.5f, 99.5f, nullptr, 0), 0.0f, 1e-6f);
  EXPECT_LE(BlendWeight(kShape, linear, -3.0f, 49.5f, nullptr, 0), 0.0f);  // outside: not painted
  // Half way to a side edge, half the weight; towards a corner the product.
  EXPECT_NEAR(BlendWeight(kShape, linear, 49.5f, 49.5f, nullptr, 0), 0.5f, 1e-5f);
  EXPECT_NEAR(BlendWeight(kShape, linear, 49.5f, 24.5f, nullptr, 0), 0.25f, 1e-5f);
  EXPECT_EQ(CanvasWeight(0.0f), 0);
  EXPECT_EQ(CanvasWeight(1e-6f), 1);
  EXPECT_EQ(CanvasWeight(1.0f), 255);
}

TEST(BlendRule, FeatherPowerFavoursTheCentre) {
  const FeatherCurve squared(2.0);
  EXPECT_FALSE(squared.IsIdentity());
  EXPECT_TRUE(FeatherCurve(1.0).IsIdentity());
  EXPECT_NEAR(BlendWeight(kShape, squared, 49.5f, 49.5f, nullptr, 0), 0.25f, 2e-3f);
  EXPECT_NEAR(squared(1.0f), 1.0f, 1e-6f);
}

TEST(BlendRule, AFrameHandsOverWhatANeighbourSeesMoreCentrally) {
  const FeatherCurve linear(1.0);
  const float inv_seam = InverseSeamWidth(0.5, 0.2f);  // the neighbour's centre at centrality 0.2
  EXPECT_NEAR(inv_seam, 1 / 0.1f, 1e-4f);
  // Both see the pixel equally centrally: the frame keeps it in full.
  NeighbourView same{120.0f, 49.5f, inv_seam};
  EXPECT_NEAR(BlendWeight(kShape, linear, 79.0f, 49.5f, &same, 1),
              BlendWeight(kShape, linear, 79.0f, 49.5f, nullptr, 0), 1e-3f);
  // The neighbour sees it at its centre, this frame near its edge: handed over.
  NeighbourView better{99.5f, 49.5f, inv_seam};
  EXPECT_EQ(BlendWeight(kShape, linear, 20.0f, 49.5f, &better, 1), 0.0f);
  // Inside the seam, a share between 0 and 1.
  NeighbourView close{99.5f - 12.0f, 49.5f, inv_seam};
  const float shared = BlendWeight(kShape, linear, 99.5f + 12.0f + 8.0f, 49.5f, &close, 1);
  const float alone = BlendWeight(kShape, linear, 99.5f + 12.0f + 8.0f, 49.5f, nullptr, 0);
  EXPECT_GT(shared, 0.05f * alone);
  EXPECT_LT(shared, 0.95f * alone);
  // A neighbour whose image does not hold the pixel takes nothing.
  NeighbourView blind{-4.0f, 49.5f, inv_seam};
  EXPECT_EQ(BlendWeight(kShape, linear, 20.0f, 49.5f, &blind, 1),
            BlendWeight(kShape, linear, 20.0f, 49.5f, nullptr, 0));
  // The more central of two frames never gives a pixel up: no hole.
  for (float u = 1; u < 199; u += 7) {
    NeighbourView other{199.0f - u, 49.5f, inv_seam};
    const float mine = BlendWeight(kShape, linear, u, 49.5f, &other, 1);
    NeighbourView me{u, 49.5f, inv_seam};
    const float theirs = BlendWeight(kShape, linear, 199.0f - u, 49.5f, &me, 1);
    EXPECT_GT(std::max(mine, theirs), 0.0f) << u;
  }
}

}  // namespace
}  // namespace seamap
