#pragma once
// The per-pixel kernels of FrameWarper: feather and handover weights four
// pixels at a time (OpenCV's universal intrinsics: SSE2 on x86, NEON on ARM
// boards), the weights' 8-bit form, and bilinear sampling. FrameWarper
// decides which pixels to visit; these only compute. Inline: they run once
// per block row and share their constants across a block when inlined.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

#include <opencv2/core/hal/intrin.hpp>

#include "core/camera/camera_model.h"

namespace seamap {
namespace warp {

constexpr int kLut = 1024;     // entries of the feather-power lookup table
constexpr int kMaxRivals = 2;  // the previous and the next painted frame
constexpr int kMaxCell = 64;   // largest grid step (pixels per block row)

// Image geometry for the per-pixel tests, in raw pixels.
struct ImageShape {
  float width, height, inv_half_w, inv_half_h, centre_u, centre_v;
  explicit ImageShape(const CameraModel& c)
      : width(static_cast<float>(c.width)),
        height(static_cast<float>(c.height)),
        inv_half_w(2.0f / c.width),
        inv_half_h(2.0f / c.height),
        centre_u((c.width - 1) / 2.0f),
        centre_v((c.height - 1) / 2.0f) {}
  // The feather tent: 1 at the centre, 0 at the raw image edges, <= 0 outside.
  float Tent(float u, float v) const {
    const float ta = std::min(u + 0.5f, width - 0.5f - u) * inv_half_w;
    const float tb = std::min(v + 0.5f, height - 0.5f - v) * inv_half_h;
    const float inside = std::min(ta * tb, 1.0f), outside = std::min(ta, 0.0f) + std::min(tb, 0.0f);
    const float is_inside = static_cast<float>((ta > 0.0f) & (tb > 0.0f));
    return outside + is_inside * (inside - outside);  // arithmetic, not a branch: vectorises
  }
  // Squared distance from the image centre in half-sizes: which frame sees a
  // pixel more centrally. Unlike the tent it does not flatten towards the
  // sides, so frames hand over along track across the whole image width.
  float Centrality(float u, float v) const {
    const float a = (u - centre_u) * inv_half_w, b = (v - centre_v) * inv_half_h;
    return a * a + b * b;
  }
  // The handover ramp, before it is clamped to [0, 1]: this frame's share of
  // a pixel it sees at (u, v) and a rival at (ru, rv). 1 where both see it
  // equally centrally, below 0 once the rival sees it better by a seam.
  float Ramp(float ru, float rv, float u, float v, float inv_seam) const {
    return (Centrality(ru, rv) - Centrality(u, v)) * inv_seam + 1.0f;
  }
};

// Bilinear sample at fixed-point (8-bit fraction) position, clamped so all
// four neighbours are inside the image (edge pixels replicate).
template <int kChannels>
inline void Sample(const uint8_t* data, size_t step, float u, float v, int max_iu, int max_iv, uint8_t* out) {
  int iu = static_cast<int>(u * 256.0f), iv = static_cast<int>(v * 256.0f);
  iu = std::clamp(iu, 0, max_iu);
  iv = std::clamp(iv, 0, max_iv);
  const int fx = iu & 255, fy = iv & 255;
  const uint8_t* r0 = data + static_cast<size_t>(iv >> 8) * step + (iu >> 8) * kChannels;
  const uint8_t* r1 = r0 + step;
  for (int ch = 0; ch < kChannels; ++ch) {
    const int top = r0[ch] * (256 - fx) + r0[ch + kChannels] * fx;
    const int bottom = r1[ch] * (256 - fx) + r1[ch + kChannels] * fx;
    out[ch] = static_cast<uint8_t>((top * (256 - fy) + bottom * fy + 32768) >> 16);
  }
}

// One pixel row of a grid block: positions in this frame and in each rival,
// linear in the pixel index i (u0 + du * i).
struct BlockRow {
  float u0 = 0, du = 0, v0 = 0, dv = 0;
  float ru0[kMaxRivals] = {0, 0}, rdu[kMaxRivals] = {0, 0}, rv0[kMaxRivals] = {0, 0}, rdv[kMaxRivals] = {0, 0};
  bool rival[kMaxRivals] = {false, false};  // false: the rival is far from seeing this block
};

// Sample<1> for the pixels of a block row whose bits are set in `mask`
// (pixel i at u0 + du * i, v0 + dv * i), four at a time: positions and
// blending in SIMD. Each pixel's two horizontal neighbours are loaded as one
// 16-bit word per row and weighted by a multiply-add of 16-bit pairs. Same
// arithmetic as Sample<1>, so the same values.
inline void SampleGray4(const uint8_t* data, size_t step, float u0, float du, float v0, float dv, int max_iu,
                        int max_iv, uint64_t mask, uint8_t* out) {
  static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the 16-bit pairs below put the left byte low");
  using cv::v_float32x4;
  using cv::v_int32x4;
  const v_float32x4 vu0 = cv::v_setall_f32(u0), vdu = cv::v_setall_f32(du);
  const v_float32x4 vv0 = cv::v_setall_f32(v0), vdv = cv::v_setall_f32(dv), scale = cv::v_setall_f32(256.0f);
  const v_int32x4 zero = cv::v_setzero_s32(), hi_u = cv::v_setall_s32(max_iu), hi_v = cv::v_setall_s32(max_iv);
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
      const uint8_t* p = data + static_cast<size_t>(row[k]) * step + col[k];
      std::memcpy(&top[k], p, 2);
      std::memcpy(&bottom[k], p + step, 2);
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

// The pixel indices i (as an open interval) at which x0 + dx * i lies in (0, limit).
inline void OpenInterval(float x0, float dx, float limit, float* lo, float* hi) {
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

// Weights of pixels [0, n) of a block row into w (room for n rounded up to
// 4): positive exactly where the pixel is inside the image, the feather tent
// there (shaped by `lut` when given), times, for each rival that sees the
// pixel more centrally, a ramp to zero across its seam; 0 or below elsewhere.
// Along a row positions are linear in i, so the ramp, a difference of
// squared distances, is a quadratic in i and the pixels a rival sees are an
// interval of i: both are worked out once per row, leaving a few SIMD
// operations per pixel (OpenCV's universal intrinsics: SSE2 here, NEON on
// ARM boards).
inline void RowWeights(const ImageShape& sh, const BlockRow& r, int rivals, const float* inv_seam, const float* lut,
                       int n, float* w) {
  using cv::v_float32x4;
  const v_float32x4 zero = cv::v_setzero_f32(), one = cv::v_setall_f32(1.0f), half = cv::v_setall_f32(0.5f);
  const v_float32x4 right = cv::v_setall_f32(sh.width - 0.5f), bottom = cv::v_setall_f32(sh.height - 0.5f);
  const v_float32x4 inv_hw = cv::v_setall_f32(sh.inv_half_w), inv_hh = cv::v_setall_f32(sh.inv_half_h);
  // Centrality along the row: c0 + c1 i + c2 i^2.
  auto centrality = [&](float u0, float du, float v0, float dv, float* c) {
    const float a0 = (u0 - sh.centre_u) * sh.inv_half_w, a1 = du * sh.inv_half_w;
    const float b0 = (v0 - sh.centre_v) * sh.inv_half_h, b1 = dv * sh.inv_half_h;
    c[0] = a0 * a0 + b0 * b0;
    c[1] = 2 * (a0 * a1 + b0 * b1);
    c[2] = a1 * a1 + b1 * b1;
  };
  float own[3];
  centrality(r.u0, r.du, r.v0, r.dv, own);
  // Per rival: the ramp's coefficients and the interval of i it sees (by half a pixel).
  v_float32x4 q0[kMaxRivals], q1[kMaxRivals], q2[kMaxRivals], lo[kMaxRivals], hi[kMaxRivals];
  int active = 0;
  for (int k = 0; k < rivals; ++k) {
    if (!r.rival[k]) continue;
    float c[3], from = -1e30f, to = 1e30f;
    centrality(r.ru0[k], r.rdu[k], r.rv0[k], r.rdv[k], c);
    OpenInterval(r.ru0[k], r.rdu[k], sh.width - 1.0f, &from, &to);
    OpenInterval(r.rv0[k], r.rdv[k], sh.height - 1.0f, &from, &to);
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
  alignas(16) float ramps[kMaxCell + 4];
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
    if (lut) {
      cv::v_store(w + i, tent);
      cv::v_store(ramps + i, factor);
    } else {
      cv::v_store(w + i, tent * factor);
    }
  }
  if (lut)
    for (int i = 0; i < n; ++i) w[i] = (w[i] > 0 ? lut[static_cast<int>(w[i] * (kLut - 1))] : w[i]) * ramps[i];
}

// Weights [0, n) to the canvas's 8 bits (0: not painted, else 1..255);
// returns which pixels are painted, bit i for pixel i.
inline uint64_t ToCanvasWeights(const float* w, int n, uint8_t* out) {
  const cv::v_float32x4 zero = cv::v_setzero_f32(), scale = cv::v_setall_f32(254.0f), bias = cv::v_setall_f32(1.5f);
  uint64_t kept = 0;
  int i = 0;
  for (; i + 16 <= n; i += 16) {
    cv::v_int32x4 q[4];
    for (int g = 0; g < 4; ++g) {
      const cv::v_float32x4 x = cv::v_load(w + i + 4 * g);
      const cv::v_float32x4 is_kept = x > zero;
      q[g] = cv::v_trunc(cv::v_select(is_kept, bias + scale * x, zero));
      kept |= static_cast<uint64_t>(cv::v_signmask(is_kept)) << (i + 4 * g);
    }
    cv::v_store(out + i, cv::v_pack_u(cv::v_pack(q[0], q[1]), cv::v_pack(q[2], q[3])));
  }
  for (; i < n; ++i) {
    const bool is_kept = w[i] > 0.0f;
    out[i] = static_cast<uint8_t>(is_kept ? 1.5f + 254.0f * w[i] : 0.0f);
    kept |= static_cast<uint64_t>(is_kept) << i;
  }
  return kept;
}

}  // namespace warp
}  // namespace seamap
