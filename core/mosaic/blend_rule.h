#pragma once
// The blending rule, written once. Each map pixel is the weighted mean of the
// frames that paint it. A frame that sees the pixel at raw image position
// (u, v) weighs it
//
//   weight = feather(tent(u, v))  x  for each neighbour that sees it too: handover
//
// - tent: 1 at the image centre, falling to 0 at the raw image edges (so
//   seams between frames are feathered and vignetted edges count little);
//   feather() raises it to `feather_power` (higher favours frame centres).
// - handover: consecutive frames overlap about 10x along track at 5 frames/s.
//   A frame hands every pixel that its previous or next frame sees more
//   centrally (smaller squared distance from the image centre, see
//   Centrality) over to that neighbour: its share ramps from 1 where both see
//   the pixel equally centrally to 0 once the neighbour sees it better by a
//   seam's width. The seam spans `seam_band` of the way from the midpoint to
//   the neighbour's centre, whatever the spacing. No pixel is lost: a pixel
//   goes only to a frame that sees it more centrally, and the most central of
//   a run of frames keeps it. Survey lines side by side are not neighbours:
//   their overlap blends in full by feather weight.
//
// These functions are the reference: one pixel at a time, as readable as it
// gets. The warper computes the same numbers a row at a time (row_kernels.h)
// and its tests hold that fast path to these functions.
#include <cstdint>
#include <vector>

#include "core/camera/camera_model.h"

namespace seamap {

// Image geometry for the weights, in raw pixels.
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
  // The handover ramp before it is clamped to [0, 1]: this frame's share of
  // a pixel it sees at (u, v) and a neighbour at (nu, nv). 1 where both see
  // it equally centrally, below 0 once the neighbour sees it better by a seam.
  float Ramp(float nu, float nv, float u, float v, float inv_seam) const {
    return (Centrality(nu, nv) - Centrality(u, v)) * inv_seam + 1.0f;
  }
  // Whether a neighbour sees the pixel: strictly inside its image.
  bool Sees(float u, float v) const { return u > 0 && u < width - 1 && v > 0 && v < height - 1; }
};

// tent -> tent^feather_power, by a table (pow per pixel is slow).
class FeatherCurve {
 public:
  static constexpr int kEntries = 1024;
  explicit FeatherCurve(double feather_power);
  bool IsIdentity() const { return table_.empty(); }  // power 1
  // tent in (0, 1].
  float operator()(float tent) const { return table_.empty() ? tent : table_[static_cast<int>(tent * (kEntries - 1))]; }
  const float* table() const { return table_.empty() ? nullptr : table_.data(); }

 private:
  std::vector<float> table_;
};

// What a neighbouring frame sees at the pixel being weighed.
struct NeighbourView {
  float u = 0, v = 0;  // its raw image position of the pixel
  float inv_seam = 1;  // 1 / the seam's width in Centrality units (see SeamWidth)
};

// The seam's width for a neighbour whose centre this frame sees at
// Centrality `spacing` (how far apart the two frames are): `seam_band` of it.
float InverseSeamWidth(double seam_band, float spacing);

// A frame's weight at a pixel it sees at (u, v): > 0 where it paints the
// pixel, <= 0 where it does not.
float BlendWeight(const ImageShape& shape, const FeatherCurve& feather, float u, float v,
                  const NeighbourView* neighbours, int neighbour_count);

// The weight as a warped frame keeps it: 0 not painted, else 1..255.
inline uint8_t CanvasWeight(float weight) {
  return static_cast<uint8_t>(weight > 0.0f ? 1.5f + 254.0f * weight : 0.0f);
}

}  // namespace seamap
