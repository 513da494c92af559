#include "core/terrain/painting_surface.h"

#include <cmath>
#include <limits>
#include <vector>

namespace seamap {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

// Keys' cubic convolution weights (a = -0.5) for a sample at fraction t of the way from tap 1 to tap 2.
void CubicWeights(double t, double w[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = -0.5 * t3 + t2 - 0.5 * t;
  w[1] = 1.5 * t3 - 2.5 * t2 + 1;
  w[2] = -1.5 * t3 + 2 * t2 + 0.5 * t;
  w[3] = 0.5 * t3 - 0.5 * t2;
}

}  // namespace

long ExtendHeightGrid(double reach_m, double slope_share, HeightGrid* grid) {
  if (grid->empty() || !(reach_m > 0) || !(grid->cell_m > 0)) return 0;
  const int rows = grid->rows(), cols = grid->cols();
  const int rings = static_cast<int>(std::ceil(reach_m / grid->cell_m));
  const auto share = static_cast<float>(slope_share);
  cv::Mat1f& h = grid->height_m;
  // 0: a hole, 1: known, 2: in the ring being filled.
  cv::Mat1b state(rows, cols, uchar(0));
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) state(r, c) = std::isfinite(h(r, c)) ? 1 : 0;
  const auto inside = [&](int r, int c) { return r >= 0 && c >= 0 && r < rows && c < cols; };
  std::vector<cv::Point> ring;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      if (state(r, c) != 0) continue;
      bool next_to_known = false;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) next_to_known |= inside(r + dr, c + dc) && state(r + dr, c + dc) == 1;
      if (next_to_known) {
        state(r, c) = 2;
        ring.emplace_back(c, r);
      }
    }
  long filled = 0;
  std::vector<float> values;
  for (int k = 0; k < rings && !ring.empty(); ++k) {
    // Every cell of the ring from the cells known before it.
    values.assign(ring.size(), 0.0f);
    for (size_t i = 0; i < ring.size(); ++i) {
      const int r = ring[i].y, c = ring[i].x;
      // Neighbours with a slope behind them (on the same line) continue it;
      // the others count only where none has one (a level continuation).
      double sum[2] = {0, 0}, weight[2] = {0, 0};
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          if ((dr == 0 && dc == 0) || !inside(r + dr, c + dc) || state(r + dr, c + dc) != 1) continue;
          const float near = h(r + dr, c + dc);
          const int sloped = inside(r + 2 * dr, c + 2 * dc) && state(r + 2 * dr, c + 2 * dc) == 1;
          const float slope = sloped ? near - h(r + 2 * dr, c + 2 * dc) : 0.0f;
          const double w = (dr != 0 && dc != 0) ? M_SQRT1_2 : 1.0;  // diagonals are further
          sum[sloped] += w * (near + share * slope);
          weight[sloped] += w;
        }
      const int use = weight[1] > 0 ? 1 : 0;
      values[i] = static_cast<float>(sum[use] / weight[use]);
    }
    for (size_t i = 0; i < ring.size(); ++i) {
      h(ring[i].y, ring[i].x) = values[i];
      if (!grid->sigma_m.empty()) grid->sigma_m(ring[i].y, ring[i].x) = kNaN;
      state(ring[i].y, ring[i].x) = 1;
    }
    filled += static_cast<long>(ring.size());
    std::vector<cv::Point> next;
    for (const cv::Point& p : ring)
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc)
          if (inside(p.y + dr, p.x + dc) && state(p.y + dr, p.x + dc) == 0) {
            state(p.y + dr, p.x + dc) = 2;
            next.emplace_back(p.x + dc, p.y + dr);
          }
    ring.swap(next);
  }
  return filled;
}

HeightGrid RefineHeightGrid(const HeightGrid& grid, int factor) {
  HeightGrid out;
  out.has_depth_datum = grid.has_depth_datum;
  if (grid.empty() || factor <= 1) {
    out = grid;
    out.height_m = grid.height_m.clone();
    out.sigma_m = cv::Mat1f();
    return out;
  }
  const int rows = grid.rows(), cols = grid.cols();
  out.cell_m = grid.cell_m / factor;
  // The same extent: the fine cells tile each model cell, centred on it.
  const double first = -(factor - 1) / (2.0 * factor);  // in model cells
  out.east0_m = grid.east0_m + first * grid.cell_m;
  out.north0_m = grid.north0_m - first * grid.cell_m;
  out.height_m.create(rows * factor, cols * factor);
  const auto at = [&](int r, int c) -> float {
    return r >= 0 && c >= 0 && r < rows && c < cols ? grid.height_m(r, c) : kNaN;
  };
  std::vector<int> c0(static_cast<size_t>(out.cols()));
  std::vector<double> wc(4 * static_cast<size_t>(out.cols())), tc(static_cast<size_t>(out.cols()));
  for (int j = 0; j < out.cols(); ++j) {
    const double x = first + static_cast<double>(j) / factor;
    c0[j] = static_cast<int>(std::floor(x));
    tc[j] = x - c0[j];
    CubicWeights(tc[j], &wc[4 * static_cast<size_t>(j)]);
  }
  for (int i = 0; i < out.rows(); ++i) {
    const double y = first + static_cast<double>(i) / factor;
    const int r0 = static_cast<int>(std::floor(y));
    const double tr = y - r0;
    double wr[4];
    CubicWeights(tr, wr);
    float* dst = out.height_m[i];
    for (int j = 0; j < out.cols(); ++j) {
      const double* w = &wc[4 * static_cast<size_t>(j)];
      double sum = 0;
      for (int a = 0; a < 4; ++a) {
        double row = 0;
        for (int b = 0; b < 4; ++b) row += w[b] * at(r0 - 1 + a, c0[j] - 1 + b);
        sum += wr[a] * row;
      }
      if (!std::isfinite(sum)) {  // a hole among the 16: bilinear from the 4, if they are known
        const double t = tc[j];
        sum = (1 - tr) * ((1 - t) * at(r0, c0[j]) + t * at(r0, c0[j] + 1)) +
              tr * ((1 - t) * at(r0 + 1, c0[j]) + t * at(r0 + 1, c0[j] + 1));
      }
      dst[j] = static_cast<float>(sum);  // NaN where the 4 are not all known
    }
  }
  return out;
}

HeightGrid PaintingSurface(const HeightGrid& model, const PaintingSurfaceOptions& options,
                           PaintingSurfaceReport* report) {
  HeightGrid extended = model;
  extended.height_m = model.height_m.clone();
  extended.sigma_m = cv::Mat1f();
  const long filled = ExtendHeightGrid(options.reach_m, options.slope_share, &extended);
  if (report) report->cells_extended = filled;
  return RefineHeightGrid(extended, options.refine);
}

}  // namespace seamap
