#include "core/mosaic/blend_rule.h"

#include <algorithm>
#include <cmath>

namespace seamap {

FeatherCurve::FeatherCurve(double feather_power) {
  if (feather_power == 1.0) return;
  table_.resize(kEntries);
  for (int i = 0; i < kEntries; ++i)
    table_[i] = static_cast<float>(std::pow(static_cast<double>(i) / (kEntries - 1), feather_power));
}

float InverseSeamWidth(double seam_band, float spacing) {
  return 1.0f / std::max(1e-6f, static_cast<float>(seam_band) * std::min(spacing, 1.0f));
}

float BlendWeight(const ImageShape& shape, const FeatherCurve& feather, float u, float v,
                  const NeighbourView* neighbours, int neighbour_count, float slant) {
  const float tent = shape.Tent(u, v);
  if (tent <= 0) return tent;
  float weight = feather(tent);
  for (int k = 0; k < neighbour_count; ++k) {
    const NeighbourView& n = neighbours[k];
    if (!shape.Sees(n.u, n.v)) continue;
    weight *= std::clamp(shape.Handover(n.u, n.v, n.slant, u, v, slant, n.inv_seam), 0.0f, 1.0f);
  }
  return weight;
}

}  // namespace seamap
