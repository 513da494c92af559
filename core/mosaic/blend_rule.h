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
// Over a height model (build --terrain) the handover compares how far from
// the vertical each frame's ray to the seabed point is (ImageShape::by_slant,
// RawPosition::slant: tan^2 of that angle) instead of the image positions:
// the frame that keeps a pixel is the most nadir view of that point, whatever
// the pitch and roll. Flat builds keep the image-centre rule, byte for byte.
//
// These functions are the reference: one pixel at a time, as readable as it
// gets. The warper computes the same numbers a row at a time (row_kernels.h)
// and its tests hold that fast path to these functions.
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/camera/camera_model.h"

namespace seamap {

// Image geometry for the weights, in raw pixels.
struct ImageShape {
  float width, height, inv_half_w, inv_half_h, centre_u, centre_v;
  bool by_slant = false;  // the handover compares slants (angle to the vertical), not Centrality
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
  // The same by whichever measure the shape hands over by: Centrality of the
  // positions, or (by_slant) the slants ns, s of the neighbour's and this frame's rays.
  float Handover(float nu, float nv, float ns, float u, float v, float s, float inv_seam) const {
    return by_slant ? (ns - s) * inv_seam + 1.0f : Ramp(nu, nv, u, v, inv_seam);
  }
  // How far apart two frames are for the seam's width: the neighbour's
  // measure at this frame's centre, less this frame's own there.
  float Spacing(float nu, float nv, float ns, float s) const {
    return by_slant ? std::fabs(ns - s) : Centrality(nu, nv);
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
  float slant = 0;     // its ray's slant there (by_slant)
};

// The seam's width for a neighbour whose centre this frame sees at
// Centrality `spacing` (how far apart the two frames are): `seam_band` of it.
float InverseSeamWidth(double seam_band, float spacing);

// A frame's weight at a pixel it sees at (u, v): > 0 where it paints the
// pixel, <= 0 where it does not.
// slant: this frame's ray's (by_slant).
float BlendWeight(const ImageShape& shape, const FeatherCurve& feather, float u, float v,
                  const NeighbourView* neighbours, int neighbour_count, float slant = 0);

// The weight as a warped frame keeps it: 0 not painted, else 1..255.
inline uint8_t CanvasWeight(float weight) {
  return static_cast<uint8_t>(weight > 0.0f ? 1.5f + 254.0f * weight : 0.0f);
}

}  // namespace seamap
