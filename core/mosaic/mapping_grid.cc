#include "core/mosaic/mapping_grid.h"

#include <algorithm>
#include <cmath>

namespace seamap {

MappingGrid::MappingGrid(const BoxMapping& own, const ImageShape& shape,
                         const std::vector<const BoxMapping*>& neighbours, const float* inv_seam, int box_width,
                         int box_height, int step)
    : shape_(shape),
      neighbours_(std::min(static_cast<int>(neighbours.size()), kMaxNeighbours)),
      step_(step),
      nx_((box_width + step - 1) / step + 1),
      ny_((box_height + step - 1) / step + 1) {
  for (int k = 0; k < neighbours_; ++k) inv_seam_[k] = inv_seam[k];
  points_.resize(static_cast<size_t>(nx_) * ny_);
  for (int gy = 0; gy < ny_; ++gy) {
    for (int gx = 0; gx < nx_; ++gx) {
      GridPoint& g = points_[static_cast<size_t>(gy) * nx_ + gx];
      const double x = gx * step, y = gy * step;
      g.own = own.ToRaw(x, y);
      // Far outside this frame the neighbours do not matter.
      if (!g.own.valid || shape.Tent(g.own.u, g.own.v) < -0.5f) continue;
      for (int k = 0; k < neighbours_; ++k) g.neighbour[k] = neighbours[k]->ToRaw(x, y);
    }
  }
  // How far the mapping moves across a block, measured at the box's centre.
  const int cx = std::min(nx_ / 2, nx_ - 2), cy = std::min(ny_ / 2, ny_ - 2);  // a box of one block has nx = 2
  const RawPosition& g = At(cx, cy).own;
  const RawPosition& gx1 = At(cx + 1, cy).own;
  const RawPosition& gy1 = At(cx, cy + 1).own;
  if (g.valid && gx1.valid && gy1.valid) {
    block_reach_ = {1.5f * (std::fabs(gx1.u - g.u) + std::fabs(gy1.u - g.u)) + 1,
                    1.5f * (std::fabs(gx1.v - g.v) + std::fabs(gy1.v - g.v)) + 1};
    row_reach_ = {1.5f * std::fabs(gx1.u - g.u) + 1, 1.5f * std::fabs(gx1.v - g.v) + 1};
  }
}

bool MappingGrid::Outside(float u, float v, const Reach& r) const {
  return u < -0.5f - r.u || u > shape_.width - 0.5f + r.u || v < -0.5f - r.v || v > shape_.height - 0.5f + r.v;
}

bool MappingGrid::InsideBy(float u, float v, const Reach& r) const {
  return u > r.u - 0.5f && u < shape_.width - 0.5f - r.u && v > r.v - 0.5f && v < shape_.height - 0.5f - r.v;
}

bool MappingGrid::TakenBy(float nu, float nv, float ns, float u, float v, float s, int k, const Reach& r) const {
  return InsideBy(nu, nv, r) && shape_.Handover(nu, nv, ns, u, v, s, inv_seam_[k]) < -0.25f;
}

bool MappingGrid::MayKeepBlock(int bx, int by) const {
  const GridPoint* corners[4] = {&At(bx, by), &At(bx + 1, by), &At(bx, by + 1), &At(bx + 1, by + 1)};
  for (const GridPoint* g : corners)
    if (!g->own.valid) return false;
  bool all_outside = true;
  for (const GridPoint* g : corners) all_outside = all_outside && Outside(g->own.u, g->own.v, block_reach_);
  if (all_outside) return false;
  for (int k = 0; k < neighbours_; ++k) {
    bool all_taken = true;
    for (const GridPoint* g : corners) {
      const RawPosition& n = g->neighbour[k];
      all_taken = all_taken && n.valid && TakenBy(n.u, n.v, n.slant, g->own.u, g->own.v, g->own.slant, k, block_reach_);
    }
    if (all_taken) return false;
  }
  return true;
}

bool MappingGrid::MayKeepRow(const BlockRow& row) const {
  const float length = static_cast<float>(step_);
  const float u1 = row.u0 + row.du * length, v1 = row.v0 + row.dv * length;
  if (Outside(row.u0, row.v0, row_reach_) && Outside(u1, v1, row_reach_)) return false;
  for (int k = 0; k < neighbours_; ++k)
    if (row.neighbour[k] && TakenBy(row.nu0[k], row.nv0[k], row.ns0[k], row.u0, row.v0, row.s0, k, row_reach_) &&
        TakenBy(row.nu0[k] + row.ndu[k] * length, row.nv0[k] + row.ndv[k] * length, row.ns0[k] + row.nds[k] * length,
                u1, v1, row.s0 + row.ds * length, k, row_reach_))
      return false;
  return true;
}

MappingGrid::Block MappingGrid::BlockAt(int bx, int by) const {
  const GridPoint& g00 = At(bx, by);
  const GridPoint& g10 = At(bx + 1, by);
  const GridPoint& g01 = At(bx, by + 1);
  const GridPoint& g11 = At(bx + 1, by + 1);
  Block b;
  b.inv_step_ = 1.0f / step_;
  auto set = [&b](int q, float c00, float c10, float c01, float c11) {
    b.left_[q] = c00;
    b.left_step_[q] = c01 - c00;
    b.right_[q] = c10;
    b.right_step_[q] = c11 - c10;
  };
  set(0, g00.own.u, g10.own.u, g01.own.u, g11.own.u);
  set(1, g00.own.v, g10.own.v, g01.own.v, g11.own.v);
  set(2, g00.own.slant, g10.own.slant, g01.own.slant, g11.own.slant);
  for (int k = 0; k < kMaxNeighbours; ++k) {
    const auto n = [k](const GridPoint& g) -> const RawPosition& { return g.neighbour[k]; };
    b.neighbour_[k] = k < neighbours_ && n(g00).valid && n(g10).valid && n(g01).valid && n(g11).valid;
    set(3 + 3 * k, n(g00).u, n(g10).u, n(g01).u, n(g11).u);
    set(4 + 3 * k, n(g00).v, n(g10).v, n(g01).v, n(g11).v);
    set(5 + 3 * k, n(g00).slant, n(g10).slant, n(g01).slant, n(g11).slant);
    // A neighbour that sees the whole block less centrally (its ramp is past
    // 1 by a quarter at every corner) leaves every weight as it is.
    if (b.neighbour_[k] && inv_seam_[k] <= 100.0f) {  // a vanishing seam is a step: no margin to trust
      bool behind = true;
      for (const GridPoint* g : {&g00, &g10, &g01, &g11})
        behind = behind && shape_.Handover(n(*g).u, n(*g).v, n(*g).slant, g->own.u, g->own.v, g->own.slant,
                                           inv_seam_[k]) >= 1.25f;
      if (behind) b.neighbour_[k] = false;
    }
  }
  return b;
}

BlockRow MappingGrid::Block::Row(int j) const {
  const float fy = j * inv_step_;
  float start[kValues], step[kValues];
  for (int q = 0; q < kValues; ++q) {
    const float left = left_[q] + left_step_[q] * fy, right = right_[q] + right_step_[q] * fy;
    start[q] = left;
    step[q] = (right - left) * inv_step_;
  }
  BlockRow r;
  r.u0 = start[0];
  r.du = step[0];
  r.v0 = start[1];
  r.dv = step[1];
  r.s0 = start[2];
  r.ds = step[2];
  for (int k = 0; k < kMaxNeighbours; ++k) {
    r.neighbour[k] = neighbour_[k];
    r.nu0[k] = start[3 + 3 * k];
    r.ndu[k] = step[3 + 3 * k];
    r.nv0[k] = start[4 + 3 * k];
    r.ndv[k] = step[4 + 3 * k];
    r.ns0[k] = start[5 + 3 * k];
    r.nds[k] = step[5 + 3 * k];
  }
  return r;
}

}  // namespace seamap
