// The warper's fast path against the reference (blend_rule.h, one pixel at a time).
#include "core/mosaic/row_kernels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "core/mosaic/frame_warper.h"

namespace seamap {
namespace {

TEST(RowKernels, FastWeightsFollowTheReference) {
  const ImageShape shape(CameraFromFocalLength(8, 12.9, 160, 120));
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> pos(-20, 180), slope(-1.2f, 1.2f);
  const FeatherCurve linear(1.0), squared(2.0);
  const float inv_seam[kMaxNeighbours] = {1 / 0.3f, 1 / 0.05f};
  int compared = 0, positive = 0, ramped = 0;
  for (int trial = 0; trial < 400; ++trial) {
    BlockRow r;
    r.u0 = pos(rng);
    r.du = slope(rng);
    r.v0 = pos(rng) * 0.7f;
    r.dv = slope(rng) * 0.3f;
    for (int k = 0; k < kMaxNeighbours; ++k) {
      r.neighbour[k] = trial % 3 != k;
      r.nu0[k] = r.u0 + pos(rng) * 0.2f - 16;
      r.ndu[k] = r.du + slope(rng) * 0.01f;
      r.nv0[k] = r.v0 + pos(rng) * 0.2f - 16;
      r.ndv[k] = r.dv + slope(rng) * 0.01f;
    }
    if (trial % 5 == 1) r.dv = r.ndv[0] = r.ndv[1] = 0;  // a north-up row: v constant along it
    if (trial % 7 == 2) r.du = r.ndu[0] = 0;
    const int n = 1 + trial % 16;
    const int neighbours = trial % 3;
    const FeatherCurve& feather = trial % 4 == 0 ? squared : linear;
    alignas(16) float fast[kMaxGridStep + 4], reference[kMaxGridStep + 4];
    RowWeights(KernelPath::kFast, shape, feather, r, neighbours, inv_seam, n, fast);
    RowWeights(KernelPath::kReference, shape, feather, r, neighbours, inv_seam, n, reference);
    for (int i = 0; i < n; ++i, ++compared) {
      // The fast path evaluates the ramp as a quadratic in i: the same to rounding.
      if (reference[i] > 0)
        ASSERT_NEAR(fast[i], reference[i], 1e-4f) << "trial " << trial << " pixel " << i;
      else
        ASSERT_LE(fast[i], 1e-4f) << "trial " << trial << " pixel " << i;
      positive += reference[i] > 0;
      ramped += &feather == &linear && reference[i] > 0 && reference[i] < shape.Tent(r.U(i), r.V(i)) * 0.99f;
    }
  }
  EXPECT_GT(positive, compared / 10);  // the rows cross the image...
  EXPECT_GT(ramped, 20);               // ...and the seams
}

TEST(RowKernels, CanvasWeightsAreEightBitAndMarkPaintedPixels) {
  const float w[20] = {0.0f, -0.5f, 0.001f, 1.0f, 0.5f, 0.0f, 0.25f, -1.0f, 0.75f, 0.999f,
                       0.0f, 0.0f,  0.1f,   0.0f, 0.3f, 1.0f, 0.2f,  0.0f,  -0.1f, 0.6f};
  for (KernelPath path : {KernelPath::kFast, KernelPath::kReference})
    for (int n : {16, 20, 5}) {
      uint8_t out[20];
      const uint64_t painted = ToCanvasWeights(path, w, n, out);
      for (int i = 0; i < n; ++i) {
        EXPECT_EQ((painted >> i) & 1, w[i] > 0 ? 1u : 0u) << i;
        EXPECT_EQ(out[i], CanvasWeight(w[i])) << i;
        EXPECT_EQ(out[i] > 0, w[i] > 0) << i;
      }
      EXPECT_EQ(painted >> n, 0u);
    }
  // A full 64-pixel row.
  std::vector<float> many(64, 0.5f);
  uint8_t out[64];
  EXPECT_EQ(ToCanvasWeights(KernelPath::kFast, many.data(), 64, out), ~uint64_t{0});
}

TEST(RowKernels, FastSamplingEqualsTheReference) {
  // A textured image; rows of positions inside, across the edges and
  // outside (clamped), with some pixels not painted.
  const int width = 40, height = 30;
  std::vector<uint8_t> pixels(width * height);
  std::mt19937 rng(5);
  for (auto& p : pixels) p = static_cast<uint8_t>(rng() & 255);
  const RawImage image{pixels.data(), static_cast<size_t>(width), width, height, 1};
  std::uniform_real_distribution<float> pos(-5, 45), slope(-1.5f, 1.5f);
  for (int trial = 0; trial < 300; ++trial) {
    BlockRow r;
    r.u0 = pos(rng);
    r.du = slope(rng);
    r.v0 = pos(rng) * 0.7f;
    r.dv = slope(rng) * 0.3f;
    const uint64_t mask = (static_cast<uint64_t>(rng()) << 32 | rng()) & 0xffff;
    uint8_t fast[16] = {}, reference[16] = {}, one[16] = {};
    SampleRow(KernelPath::kFast, image, r, mask, fast);
    SampleRow(KernelPath::kReference, image, r, mask, reference);
    for (int i = 0; i < 16; ++i)
      if (mask >> i & 1) SampleBilinear(image, r.U(i), r.V(i), one + i);
    for (int i = 0; i < 16; ++i) {
      ASSERT_EQ(fast[i], reference[i]) << "trial " << trial << " pixel " << i;
      ASSERT_EQ(reference[i], one[i]) << "trial " << trial << " pixel " << i;
    }
  }
}

TEST(RowKernels, AWholeWarpOnTheFastPathEqualsTheReferencePath) {
  // A distorted, tilted frame between two neighbours, gray and colour, with
  // a shaped feather: the same pixels painted, with the same values and,
  // but for rounding at a handful of pixels, the same weights.
  CameraModel cam = CameraFromFocalLength(8, 12.9, 320, 240);
  cam.distortion = {-0.2, 0.05, 0.001, -0.001, 0};
  LocalFrame frame({43.1, 131.9});
  VehiclePose pose, behind, ahead;
  pose.altitude_m = 2.0;
  pose.heading_deg = 20;
  pose.pitch_deg = 4;
  pose.roll_deg = -3;
  behind = ahead = pose;
  behind.north_m = -0.08;
  ahead.north_m = 0.09;
  ahead.east_m = 0.02;
  for (int channels : {1, 3}) {
    cv::Mat image(cam.height, cam.width, channels == 1 ? CV_8UC1 : CV_8UC3);
    cv::randu(image, 0, 256);
    WarpOptions options;
    options.channels = channels;
    options.seam_band = 0.5;
    options.feather_power = 1.5;
    const FrameWarper fast(cam, frame, 25, 256, options);
    options.kernels = KernelPath::kReference;
    const FrameWarper reference(cam, frame, 25, 256, options);
    const auto a = fast.Warp(image, pose, {behind, ahead});
    const auto b = reference.Warp(image, pose, {behind, ahead});
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->x0, b->x0);
    ASSERT_EQ(a->y0, b->y0);
    ASSERT_EQ(a->weight.size(), b->weight.size());
    const int painted = cv::countNonZero(b->weight);
    EXPECT_GT(painted, 5000);
    cv::Mat differ = a->weight != b->weight;
    EXPECT_LE(cv::countNonZero(differ), painted / 1000) << channels << " channels";
    cv::Mat weight_diff;
    cv::absdiff(a->weight, b->weight, weight_diff);
    double worst = 0;
    cv::minMaxLoc(weight_diff, nullptr, &worst);
    EXPECT_LE(worst, 1);
    int values_differ = 0;
    for (int y = 0; y < a->pixels.rows; ++y)
      for (int x = 0; x < a->pixels.cols; ++x)
        if (a->weight.at<uint8_t>(y, x) && b->weight.at<uint8_t>(y, x))
          values_differ += std::memcmp(a->pixels.ptr<uint8_t>(y) + x * channels,
                                       b->pixels.ptr<uint8_t>(y) + x * channels, channels) != 0;
    EXPECT_EQ(values_differ, 0) << channels << " channels";
  }
}

}  // namespace
}  // namespace seamap
