#pragma once
// The map-to-image mapping of a frame (and of its neighbours) over the
// frame's box on the map, evaluated exactly every `step` map pixels and
// interpolated bilinearly in between: the mapping is smooth (homography and
// lens polynomial), so at the default step of 16 it stays within a few
// hundredths of a pixel of the exact one (tested against step 1) at a 256th
// of the cost. A block is the square between four grid points; along one
// pixel row of a block every position is linear in the pixel index.
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "core/mosaic/blend_rule.h"
#include "core/mosaic/box_mapping.h"
#include "core/mosaic/seabed_projection.h"

namespace seamap {

constexpr int kMaxNeighbours = 2;  // the previous and the next painted frame
constexpr int kMaxGridStep = 64;   // pixels per block row (a bit per pixel in a 64-bit mask)

// One exactly evaluated grid point: where this frame and each neighbour see it.
struct GridPoint {
  RawPosition own;
  RawPosition neighbour[kMaxNeighbours];
};

// One pixel row of a block: positions in this frame and in each neighbour,
// linear in the pixel index i (u0 + du * i).
struct BlockRow {
  float u0 = 0, du = 0, v0 = 0, dv = 0;
  float s0 = 0, ds = 0;  // the slant (RawPosition::slant), linear too
  float nu0[kMaxNeighbours] = {0, 0}, ndu[kMaxNeighbours] = {0, 0};
  float nv0[kMaxNeighbours] = {0, 0}, ndv[kMaxNeighbours] = {0, 0};
  float ns0[kMaxNeighbours] = {0, 0}, nds[kMaxNeighbours] = {0, 0};
  bool neighbour[kMaxNeighbours] = {false, false};  // false: this neighbour does not matter in the block
  float U(float i) const { return u0 + du * i; }
  float V(float i) const { return v0 + dv * i; }
  float S(float i) const { return s0 + ds * i; }
};

// How far (raw pixels) the mapping moves across a block, or along a row
// across a block, with room to spare.
struct Reach {
  float u = 32, v = 32;
};

class MappingGrid {
 public:
  // own: this frame's mapping; neighbours: theirs over the same box, with
  // their seams' inverse widths (blend_rule.h).
  MappingGrid(const BoxMapping& own, const ImageShape& shape, const std::vector<const BoxMapping*>& neighbours,
              const float* inv_seam, int box_width, int box_height, int step);

  int step() const { return step_; }
  int blocks_x() const { return nx_ - 1; }
  int blocks_y() const { return ny_ - 1; }

  // Whether block (bx, by) may hold a pixel the frame keeps: not if its
  // corners are all clearly outside the image, nor if one neighbour clearly
  // sees them all, and more centrally ("clearly": by more than the mapping
  // moves across the block, and by a quarter of the seam). So skipping what
  // this rules out never loses a pixel the frame keeps.
  bool MayKeepBlock(int bx, int by) const;
  // The mapping over block (bx, by), row by row.
  class Block {
   public:
    BlockRow Row(int j) const;

   private:
    friend class MappingGrid;
    static constexpr int kValues = 3 + 3 * kMaxNeighbours;  // u, v, slant, then each neighbour's
    // At the block's top-left and top-right corners, and their change down the block.
    float left_[kValues], left_step_[kValues], right_[kValues], right_step_[kValues];
    bool neighbour_[kMaxNeighbours];
    float inv_step_;
  };
  Block BlockAt(int bx, int by) const;
  // The same test for a row's ends: the handover line crosses blocks,
  // leaving some of their rows to the neighbours.
  bool MayKeepRow(const BlockRow& row) const;

 private:
  const GridPoint& At(int gx, int gy) const { return points_[static_cast<size_t>(gy) * nx_ + gx]; }
  bool Outside(float u, float v, const Reach& r) const;
  bool InsideBy(float u, float v, const Reach& r) const;
  // Neighbour k, at (nu, nv) with slant ns, clearly sees the pixel this frame
  // sees at (u, v) with slant s, and more centrally (or more nadir).
  bool TakenBy(float nu, float nv, float ns, float u, float v, float s, int k, const Reach& r) const;

  const ImageShape& shape_;
  int neighbours_;
  float inv_seam_[kMaxNeighbours] = {1, 1};
  int step_, nx_, ny_;
  std::vector<GridPoint> points_;
  Reach block_reach_, row_reach_;
};

}  // namespace seamap
