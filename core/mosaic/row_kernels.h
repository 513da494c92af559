#pragma once
// The warper's per-pixel work along one block row (positions linear in the
// pixel index, see MappingGrid): the blending weights and bilinear sampling.
// Each has a reference path, which calls blend_rule.h's BlendWeight and
// samples one pixel at a time, and a fast path that computes the same values
// four pixels at a time with OpenCV's universal intrinsics (SSE2 on x86, NEON
// on ARM boards). The warper takes the fast path; tests hold it to the
// reference, and scripts/bench.sh measures what it saves.
#include <cstddef>
#include <cstdint>

#include "core/mosaic/blend_rule.h"
#include "core/mosaic/mapping_grid.h"

namespace seamap {

enum class KernelPath { kFast, kReference };

// Weights of pixels [0, n) of a block row into w (room for n rounded up to
// 4), as BlendWeight gives them for the row's positions: > 0 exactly where
// the frame paints the pixel. `neighbours` of the row's neighbour slots are
// in use (those whose BlockRow::neighbour flag is false are left out).
void RowWeights(KernelPath path, const ImageShape& shape, const FeatherCurve& feather, const BlockRow& row,
                int neighbours, const float* inv_seam, int n, float* w);

// Weights [0, n) to 8 bits (CanvasWeight); returns which pixels are painted, bit i for pixel i.
uint64_t ToCanvasWeights(KernelPath path, const float* w, int n, uint8_t* out);

// The raw image the warp samples: 8-bit, `channels` 1 or 3, rows `step` bytes
// apart. Positions are clamped so that all four neighbours of a sample are
// inside the image (edge pixels replicate).
struct RawImage {
  const uint8_t* data;
  size_t step;
  int width, height, channels;
};

// Bilinear sample at a raw image position, in fixed point (8-bit fractions).
void SampleBilinear(const RawImage& image, float u, float v, uint8_t* out);

// Samples the pixels of a block row whose bits are set in `mask` into out
// (pixel i at out + channels * i); the others are left as they are.
void SampleRow(KernelPath path, const RawImage& image, const BlockRow& row, uint64_t mask, uint8_t* out);

}  // namespace seamap
