#include "core/mosaic/row_kernels.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <opencv2/core/hal/intrin.hpp>

namespace seamap {
namespace {

// ---- Weights -------------------------------------------------------------

void RowWeightsReference(const ImageShape& shape, const FeatherCurve& feather, const BlockRow& r, int neighbours,
                         const float* inv_seam, int n, float* w) {
  for (int i = 0; i < n; ++i) {
    const float f = static_cast<float>(i);
    NeighbourView views[kMaxNeighbours];
    int count = 0;
    for (int k = 0; k < neighbours; ++k)
      if (r.neighbour[k])
        views[count++] = {r.nu0[k] + r.ndu[k] * f, r.nv0[k] + r.ndv[k] * f, inv_seam[k], r.ns0[k] + r.nds[k] * f};
    w[i] = BlendWeight(shape, feather, r.U(f), r.V(f), views, count, r.S(f));
  }
}

// The pixel indices i (as an open interval) at which x0 + dx * i lies in (0, limit).
void OpenInterval(float x0, float dx, float limit, float* lo, float* hi) {
  if (!std::isfinite(x0) || !std::isfinite(dx)) {  // no position: sees nothing
    *lo = 1e30f;
    *hi = -1e30f;
  } else if (dx > 0) {
    *lo = std::max(*lo, -x0 / dx);
    *hi = std::min(*hi, (limit - x0) / dx);
  } else if (dx < 0) {
    *lo = std::max(*lo, (limit - x0) / dx);
    *hi = std::min(*hi, -x0 / dx);
  } else if (!(x0 > 0 && x0 < limit)) {
    *lo = 1e30f;
    *hi = -1e30f;
  }
}

// Along a row positions are linear in i, so the ramp, a difference of
// squared distances, is a quadratic in i, and the pixels a neighbour sees
// are an interval of i: both are worked out once per row, leaving a few
// SIMD operations per pixel.
void RowWeightsFast(const ImageShape& sh, const FeatherCurve& feather, const BlockRow& r, int neighbours,
                    const float* inv_seam, int n, float* w) {
  using cv::v_float32x4;
  const v_float32x4 zero = cv::v_setzero_f32(), one = cv::v_setall_f32(1.0f), half = cv::v_setall_f32(0.5f);
  const v_float32x4 right = cv::v_setall_f32(sh.width - 0.5f), bottom = cv::v_setall_f32(sh.height - 0.5f);
  const v_float32x4 inv_hw = cv::v_setall_f32(sh.inv_half_w), inv_hh = cv::v_setall_f32(sh.inv_half_h);
  // Centrality along the row: c0 + c1 i + c2 i^2 (by_slant: the slant, linear).
  auto centrality = [&](float u0, float du, float v0, float dv, float* c) {
    const float a0 = (u0 - sh.centre_u) * sh.inv_half_w, a1 = du * sh.inv_half_w;
    const float b0 = (v0 - sh.centre_v) * sh.inv_half_h, b1 = dv * sh.inv_half_h;
    c[0] = a0 * a0 + b0 * b0;
    c[1] = 2 * (a0 * a1 + b0 * b1);
    c[2] = a1 * a1 + b1 * b1;
  };
  float own[3];
  const auto measure = [&](float u0, float du, float v0, float dv, float s0, float ds, float* c) {
    if (sh.by_slant) {
      c[0] = s0;
      c[1] = ds;
      c[2] = 0;
    } else {
      centrality(u0, du, v0, dv, c);
    }
  };
  measure(r.u0, r.du, r.v0, r.dv, r.s0, r.ds, own);
  // Per neighbour: the ramp's coefficients and the interval of i it sees.
  v_float32x4 q0[kMaxNeighbours], q1[kMaxNeighbours], q2[kMaxNeighbours], lo[kMaxNeighbours], hi[kMaxNeighbours];
  int active = 0;
  for (int k = 0; k < neighbours; ++k) {
    if (!r.neighbour[k]) continue;
    float c[3], from = -1e30f, to = 1e30f;
    measure(r.nu0[k], r.ndu[k], r.nv0[k], r.ndv[k], r.ns0[k], r.nds[k], c);
    OpenInterval(r.nu0[k], r.ndu[k], sh.width - 1.0f, &from, &to);
    OpenInterval(r.nv0[k], r.ndv[k], sh.height - 1.0f, &from, &to);
    q0[active] = cv::v_setall_f32((c[0] - own[0]) * inv_seam[k] + 1.0f);
    q1[active] = cv::v_setall_f32((c[1] - own[1]) * inv_seam[k]);
    q2[active] = cv::v_setall_f32((c[2] - own[2]) * inv_seam[k]);
    lo[active] = cv::v_setall_f32(from);
    hi[active] = cv::v_setall_f32(to);
    ++active;
  }
  const v_float32x4 u0 = cv::v_setall_f32(r.u0), du = cv::v_setall_f32(r.du);
  const v_float32x4 v0 = cv::v_setall_f32(r.v0), dv = cv::v_setall_f32(r.dv);
  v_float32x4 idx(0.0f, 1.0f, 2.0f, 3.0f);
  const v_float32x4 four = cv::v_setall_f32(4.0f);
  const bool shaped = !feather.IsIdentity();
  alignas(16) float ramps[kMaxGridStep + 4];
  for (int i = 0; i < n; i += 4, idx = idx + four) {
    const v_float32x4 u = u0 + du * idx, v = v0 + dv * idx;
    const v_float32x4 ta = cv::v_min(u + half, right - u) * inv_hw;
    const v_float32x4 tb = cv::v_min(v + half, bottom - v) * inv_hh;
    const v_float32x4 tent = cv::v_min(cv::v_max(ta, zero) * cv::v_max(tb, zero), one);
    const v_float32x4 idx2 = idx * idx;
    v_float32x4 factor = one;
    for (int k = 0; k < active; ++k) {
      const v_float32x4 ramp = cv::v_min(cv::v_max(q0[k] + q1[k] * idx + q2[k] * idx2, zero), one);
      factor = factor * cv::v_select((idx > lo[k]) & (idx < hi[k]), ramp, one);
    }
    if (shaped) {
      cv::v_store(w + i, tent);
      cv::v_store(ramps + i, factor);
    } else {
      cv::v_store(w + i, tent * factor);
    }
  }
  if (shaped)
    for (int i = 0; i < n; ++i) w[i] = (w[i] > 0 ? feather(w[i]) : w[i]) * ramps[i];
}

uint64_t ToCanvasWeightsReference(const float* w, int n, uint8_t* out) {
  uint64_t painted = 0;
  for (int i = 0; i < n; ++i) {
    out[i] = CanvasWeight(w[i]);
    painted |= static_cast<uint64_t>(w[i] > 0.0f) << i;
  }
  return painted;
}

uint64_t ToCanvasWeightsFast(const float* w, int n, uint8_t* out) {
  const cv::v_float32x4 zero = cv::v_setzero_f32(), scale = cv::v_setall_f32(254.0f), bias = cv::v_setall_f32(1.5f);
  uint64_t painted = 0;
  int i = 0;
  for (; i + 16 <= n; i += 16) {
    cv::v_int32x4 q[4];
    for (int g = 0; g < 4; ++g) {
      const cv::v_float32x4 x = cv::v_load(w + i + 4 * g);
      const cv::v_float32x4 is_painted = x > zero;
      q[g] = cv::v_trunc(cv::v_select(is_painted, bias + scale * x, zero));
      painted |= static_cast<uint64_t>(cv::v_signmask(is_painted)) << (i + 4 * g);
    }
    cv::v_store(out + i, cv::v_pack_u(cv::v_pack(q[0], q[1]), cv::v_pack(q[2], q[3])));
  }
  if (i < n) painted |= ToCanvasWeightsReference(w + i, n - i, out + i) << i;
  return painted;
}

// ---- Sampling ------------------------------------------------------------

template <int kChannels>
inline void Sample(const RawImage& im, float u, float v, uint8_t* out) {
  const int iu = std::clamp(static_cast<int>(u * 256.0f), 0, (im.width - 1) * 256 - 1);
  const int iv = std::clamp(static_cast<int>(v * 256.0f), 0, (im.height - 1) * 256 - 1);
  const int fx = iu & 255, fy = iv & 255;
  const uint8_t* r0 = im.data + static_cast<size_t>(iv >> 8) * im.step + (iu >> 8) * kChannels;
  const uint8_t* r1 = r0 + im.step;
  for (int ch = 0; ch < kChannels; ++ch) {
    const int top = r0[ch] * (256 - fx) + r0[ch + kChannels] * fx;
    const int bottom = r1[ch] * (256 - fx) + r1[ch + kChannels] * fx;
    out[ch] = static_cast<uint8_t>((top * (256 - fy) + bottom * fy + 32768) >> 16);
  }
}

template <int kChannels>
void SampleRowReference(const RawImage& im, const BlockRow& r, uint64_t mask, uint8_t* out) {
  for (; mask; mask &= mask - 1) {
    const int i = __builtin_ctzll(mask);
    const float f = static_cast<float>(i);
    Sample<kChannels>(im, r.U(f), r.V(f), out + kChannels * i);
  }
}

// Gray, four pixels at a time: positions and blending in SIMD, each pixel's
// two horizontal neighbours loaded as one 16-bit word per row and weighted
// by a multiply-add of 16-bit pairs. The same arithmetic as Sample<1>.
void SampleGrayRowFast(const RawImage& im, const BlockRow& r, uint64_t mask, uint8_t* out) {
  static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the 16-bit pairs below put the left byte low");
  using cv::v_float32x4;
  using cv::v_int32x4;
  const v_float32x4 vu0 = cv::v_setall_f32(r.u0), vdu = cv::v_setall_f32(r.du);
  const v_float32x4 vv0 = cv::v_setall_f32(r.v0), vdv = cv::v_setall_f32(r.dv), scale = cv::v_setall_f32(256.0f);
  const v_int32x4 zero = cv::v_setzero_s32(), hi_u = cv::v_setall_s32((im.width - 1) * 256 - 1),
                  hi_v = cv::v_setall_s32((im.height - 1) * 256 - 1);
  const v_int32x4 frac = cv::v_setall_s32(255), one = cv::v_setall_s32(256), round = cv::v_setall_s32(32768);
  while (mask) {
    const int g = __builtin_ctzll(mask) & ~3;  // first pixel of the next group with a painted pixel
    const unsigned bits = static_cast<unsigned>(mask >> g) & 15u;
    mask &= ~(uint64_t{15} << g);
    const v_float32x4 idx(static_cast<float>(g), static_cast<float>(g + 1), static_cast<float>(g + 2),
                          static_cast<float>(g + 3));
    const v_int32x4 iu = cv::v_min(cv::v_max(cv::v_trunc((vu0 + vdu * idx) * scale), zero), hi_u);
    const v_int32x4 iv = cv::v_min(cv::v_max(cv::v_trunc((vv0 + vdv * idx) * scale), zero), hi_v);
    const v_int32x4 fx = iu & frac, fy = iv & frac;
    alignas(16) int col[4], row[4];
    cv::v_store_aligned(col, iu >> 8);
    cv::v_store_aligned(row, iv >> 8);
    uint16_t top[4], bottom[4];  // (left, right) neighbour bytes, in memory order
    for (int k = 0; k < 4; ++k) {
      const uint8_t* p = im.data + static_cast<size_t>(row[k]) * im.step + col[k];
      std::memcpy(&top[k], p, 2);
      std::memcpy(&bottom[k], p + im.step, 2);
    }
    cv::v_uint16x8 tops, bottoms;  // per pixel: left, right
    cv::v_expand(cv::v_reinterpret_as_u8(
                     cv::v_uint16x8(top[0], top[1], top[2], top[3], bottom[0], bottom[1], bottom[2], bottom[3])),
                 tops, bottoms);
    // Per pixel the 16-bit pair (256 - fx, fx): left * (256 - fx) + right * fx in one multiply-add.
    const cv::v_int16x8 wx = cv::v_reinterpret_as_s16((one - fx) | (fx << 16));
    const v_int32x4 upper = cv::v_dotprod(cv::v_reinterpret_as_s16(tops), wx);
    const v_int32x4 lower = cv::v_dotprod(cv::v_reinterpret_as_s16(bottoms), wx);
    alignas(16) int value[4];
    cv::v_store_aligned(value, (upper * (one - fy) + lower * fy + round) >> 16);
    for (int k = 0; k < 4; ++k)
      if (bits & (1u << k)) out[g + k] = static_cast<uint8_t>(value[k]);
  }
}

}  // namespace

void RowWeights(KernelPath path, const ImageShape& shape, const FeatherCurve& feather, const BlockRow& row,
                int neighbours, const float* inv_seam, int n, float* w) {
  if (path == KernelPath::kFast)
    RowWeightsFast(shape, feather, row, neighbours, inv_seam, n, w);
  else
    RowWeightsReference(shape, feather, row, neighbours, inv_seam, n, w);
}

uint64_t ToCanvasWeights(KernelPath path, const float* w, int n, uint8_t* out) {
  return path == KernelPath::kFast ? ToCanvasWeightsFast(w, n, out) : ToCanvasWeightsReference(w, n, out);
}

void SampleBilinear(const RawImage& image, float u, float v, uint8_t* out) {
  if (image.channels == 1)
    Sample<1>(image, u, v, out);
  else
    Sample<3>(image, u, v, out);
}

void SampleRow(KernelPath path, const RawImage& image, const BlockRow& row, uint64_t mask, uint8_t* out) {
  if (image.channels == 3)
    SampleRowReference<3>(image, row, mask, out);  // colour has no fast path
  else if (path == KernelPath::kFast)
    SampleGrayRowFast(image, row, mask, out);
  else
    SampleRowReference<1>(image, row, mask, out);
}

}  // namespace seamap
