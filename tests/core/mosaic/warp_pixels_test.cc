#include "core/mosaic/warp_pixels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace seamap::warp {
namespace {

// The scalar rule the SIMD kernel must follow where it is positive: tent
// (shaped by the table), times for each rival that sees the pixel by half a
// pixel the ramp clamped to [0, 1]. (Where the tent is 0 or below, the
// kernel's weight is too.)
float ReferenceWeight(const ImageShape& sh, const BlockRow& r, int rivals, const float* inv_seam, const float* lut,
                      int i) {
  const float f = static_cast<float>(i);
  const float u = r.u0 + r.du * f, v = r.v0 + r.dv * f;
  float w = sh.Tent(u, v);
  if (lut && w > 0) w = lut[static_cast<int>(w * (kLut - 1))];
  for (int k = 0; k < rivals; ++k) {
    if (!r.rival[k]) continue;
    const float ru = r.ru0[k] + r.rdu[k] * f, rv = r.rv0[k] + r.rdv[k] * f;
    if (!(ru > 0 && ru < sh.width - 1 && rv > 0 && rv < sh.height - 1)) continue;
    const float ramp = (sh.Centrality(ru, rv) - sh.Centrality(u, v)) * inv_seam[k] + 1.0f;
    w *= std::min(std::max(ramp, 0.0f), 1.0f);
  }
  return w;
}

TEST(WarpPixels, RowWeightsFollowTheScalarRule) {
  const ImageShape sh(CameraFromFocalLength(8, 12.9, 160, 120));
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> pos(-20, 180), slope(-1.2f, 1.2f);
  std::vector<float> lut(kLut);
  for (int i = 0; i < kLut; ++i) lut[i] = std::pow(static_cast<float>(i) / (kLut - 1), 2.0f);
  const float inv_seam[kMaxRivals] = {1 / 0.3f, 1 / 0.05f};
  int compared = 0, positive = 0, ramped = 0;
  for (int trial = 0; trial < 400; ++trial) {
    BlockRow r;
    r.u0 = pos(rng);
    r.du = slope(rng);
    r.v0 = pos(rng) * 0.7f;
    r.dv = slope(rng) * 0.3f;
    for (int k = 0; k < kMaxRivals; ++k) {
      r.rival[k] = trial % 3 != k;
      r.ru0[k] = r.u0 + pos(rng) * 0.2f - 16;
      r.rdu[k] = r.du + slope(rng) * 0.01f;
      r.rv0[k] = r.v0 + pos(rng) * 0.2f - 16;
      r.rdv[k] = r.dv + slope(rng) * 0.01f;
    }
    if (trial % 5 == 1) r.dv = r.rdv[0] = r.rdv[1] = 0;  // a north-up row: v constant along it
    if (trial % 7 == 2) r.du = r.rdu[0] = 0;
    const int n = 1 + trial % 16;
    const int rivals = trial % 3;
    const float* table = trial % 4 == 0 ? lut.data() : nullptr;
    alignas(16) float w[kMaxCell + 4];
    RowWeights(sh, r, rivals, inv_seam, table, n, w);
    for (int i = 0; i < n; ++i, ++compared) {
      const float expected = ReferenceWeight(sh, r, rivals, inv_seam, table, i);
      // The kernel evaluates the ramp as a quadratic in i: the same to rounding.
      if (expected > 0)
        ASSERT_NEAR(w[i], expected, 1e-4f) << "trial " << trial << " pixel " << i;
      else
        ASSERT_LE(w[i], 1e-4f) << "trial " << trial << " pixel " << i;
      positive += expected > 0;
      ramped += !table && expected > 0 && expected < sh.Tent(r.u0 + r.du * i, r.v0 + r.dv * i) * 0.99f;
    }
  }
  EXPECT_GT(positive, compared / 10);  // the rows cross the image...
  EXPECT_GT(ramped, 20);               // ...and the seams
}

TEST(WarpPixels, CanvasWeightsAreEightBitAndMarkPaintedPixels) {
  const float w[20] = {0.0f, -0.5f, 0.001f, 1.0f, 0.5f, 0.0f, 0.25f, -1.0f, 0.75f, 0.999f,
                       0.0f, 0.0f,  0.1f,   0.0f, 0.3f, 1.0f, 0.2f,  0.0f,  -0.1f, 0.6f};
  for (int n : {16, 20, 5}) {
    uint8_t out[20];
    const uint64_t painted = ToCanvasWeights(w, n, out);
    for (int i = 0; i < n; ++i) {
      const bool kept = w[i] > 0;
      EXPECT_EQ((painted >> i) & 1, kept ? 1u : 0u) << i;
      EXPECT_EQ(out[i], kept ? static_cast<uint8_t>(1.5f + 254.0f * w[i]) : 0) << i;
    }
    EXPECT_EQ(painted >> n, 0u);
  }
}

TEST(WarpPixels, FourAtATimeSamplesAsOneAtATime) {
  // A textured image; rows of positions inside, across the edges and
  // outside (clamped), with some pixels not painted.
  const int width = 40, height = 30;
  std::vector<uint8_t> image(width * height);
  std::mt19937 rng(5);
  for (auto& p : image) p = static_cast<uint8_t>(rng() & 255);
  const int max_iu = (width - 1) * 256 - 1, max_iv = (height - 1) * 256 - 1;
  std::uniform_real_distribution<float> pos(-5, 45), slope(-1.5f, 1.5f);
  for (int trial = 0; trial < 300; ++trial) {
    const float u0 = pos(rng), du = slope(rng), v0 = pos(rng) * 0.7f, dv = slope(rng) * 0.3f;
    const uint64_t mask = (static_cast<uint64_t>(rng()) << 32 | rng()) & 0xffff;
    uint8_t four[16] = {}, one[16] = {};
    SampleGray4(image.data(), width, u0, du, v0, dv, max_iu, max_iv, mask, four);
    for (int i = 0; i < 16; ++i)
      if (mask >> i & 1) Sample<1>(image.data(), width, u0 + du * i, v0 + dv * i, max_iu, max_iv, one + i);
    for (int i = 0; i < 16; ++i) ASSERT_EQ(four[i], one[i]) << "trial " << trial << " pixel " << i;
  }
}

}  // namespace
}  // namespace seamap::warp
