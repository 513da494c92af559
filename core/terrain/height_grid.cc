#include "core/terrain/height_grid.h"

#include <algorithm>
#include <cmath>

namespace seamap {

bool HeightGrid::Sample(LocalXY p, double* height_m_out, double* sigma_m_out) const {
  if (empty()) return false;
  double row = 0, col = 0;
  CellOf(p, &row, &col);
  // The last row/column is reachable exactly (interpolation weight 0 beyond it).
  if (!(row >= 0 && col >= 0 && row <= rows() - 1 && col <= cols() - 1)) return false;
  const int r0 = std::min(static_cast<int>(row), rows() - 1), c0 = std::min(static_cast<int>(col), cols() - 1);
  const int r1 = std::min(r0 + 1, rows() - 1), c1 = std::min(c0 + 1, cols() - 1);
  const double fr = row - r0, fc = col - c0;
  const double w[4] = {(1 - fr) * (1 - fc), (1 - fr) * fc, fr * (1 - fc), fr * fc};
  const int rr[4] = {r0, r0, r1, r1}, cc[4] = {c0, c1, c0, c1};
  double h = 0, s = 0;
  for (int k = 0; k < 4; ++k) {
    const float hk = height_m(rr[k], cc[k]);
    if (w[k] > 0 && !std::isfinite(hk)) return false;
    if (w[k] > 0) {
      h += w[k] * hk;
      const float sk = sigma_m.empty() ? 0.f : sigma_m(rr[k], cc[k]);
      s += w[k] * (std::isfinite(sk) ? sk : 0.f);
    }
  }
  *height_m_out = h;
  if (sigma_m_out) *sigma_m_out = s;
  return true;
}

}  // namespace seamap
