#include "core/terrain/height_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

constexpr long kMaxCells = 200L * 1000 * 1000;  // 800 MB of heights: beyond, the cell is a typo
// How far (in radii) the points' weighted centroid may lie from a cell centre.
constexpr double kMaxCentroidOffset = 0.6;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct UsablePoint {
  double east, north, up, sigma;
};

// Points bucketed by grid cell (counting sort), for neighbourhood queries.
struct PointIndex {
  int rows = 0, cols = 0;
  std::vector<int> start, order;
  void Build(const std::vector<UsablePoint>& points, const HeightGrid& grid) {
    rows = grid.rows();
    cols = grid.cols();
    std::vector<int> cell_of(points.size(), -1);
    start.assign(static_cast<size_t>(rows) * cols + 1, 0);
    for (size_t k = 0; k < points.size(); ++k) {
      double r = 0, c = 0;
      grid.CellOf({points[k].east, points[k].north}, &r, &c);
      const int ri = static_cast<int>(std::lround(r)), ci = static_cast<int>(std::lround(c));
      if (ri < 0 || ci < 0 || ri >= rows || ci >= cols) continue;
      cell_of[k] = ri * cols + ci;
      ++start[cell_of[k] + 1];
    }
    for (size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    order.assign(start.back(), 0);
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (size_t k = 0; k < points.size(); ++k)
      if (cell_of[k] >= 0) order[fill[cell_of[k]]++] = static_cast<int>(k);
  }
};

double WeightedMedian(std::vector<std::pair<double, double>> value_weight) {
  std::sort(value_weight.begin(), value_weight.end());
  double total = 0;
  for (const auto& v : value_weight) total += v.second;
  double run = 0;
  for (const auto& v : value_weight) {
    run += v.second;
    if (run >= total / 2) return v.first;
  }
  return value_weight.empty() ? 0 : value_weight.back().first;
}

struct CellFit {
  bool ok = false;
  double height = 0, sigma = 0;
  double spread = 0;  // robust spread of the residuals, metres
};

// The robust local surface (plane or quadric) at (east, north) through the points given.
CellFit FitCell(const std::vector<UsablePoint>& points, const std::vector<int>& near, double east, double north,
                double radius_m, int min_points) {
  CellFit fit;
  const int n = static_cast<int>(near.size());
  if (n < min_points) return fit;
  std::vector<double> kernel(n), dx(n), dy(n), up(n), sigma(n), residual(n), weight(n);
  std::vector<std::pair<double, double>> for_median;
  for (int k = 0; k < n; ++k) {
    const UsablePoint& p = points[near[k]];
    dx[k] = (p.east - east) / radius_m;
    dy[k] = (p.north - north) / radius_m;
    const double q = std::min(1.0, dx[k] * dx[k] + dy[k] * dy[k]);
    kernel[k] = (1 - q) * (1 - q) + 1e-3;
    up[k] = p.up;
    sigma[k] = p.sigma;
    for_median.push_back({p.up, kernel[k] / (sigma[k] * sigma[k])});
  }
  // A plane needs the points spread in two directions (else a weighted
  // mean); with enough of them a quadric, so a curved seabed does not bias
  // the centre.
  Eigen::Matrix2d spread_xy = Eigen::Matrix2d::Zero();
  for (int k = 0; k < n; ++k)
    spread_xy += Eigen::Vector2d(dx[k], dy[k]) * Eigen::Vector2d(dx[k], dy[k]).transpose() / n;
  const bool spread_out = spread_xy.determinant() > 0.01 * 0.01;
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  using Matrix6 = Eigen::Matrix<double, 6, 6>;
  int params = 1;
  auto basis = [&](int k) {
    Vector6 a = Vector6::Zero();
    a[0] = 1;
    if (params >= 3) a.segment<2>(1) << dx[k], dy[k];
    if (params >= 6) a.segment<3>(3) << dx[k] * dx[k], dx[k] * dy[k], dy[k] * dy[k];
    return a;
  };
  // Robust start: the weighted median and the spread of the points about it
  // (the slope included); points beyond three spreads do not vote. Then the
  // surface by weighted least squares, twice, the second time over the
  // points within three robust spreads (or three of their own sigmas) of the first.
  const double start = WeightedMedian(for_median);
  auto robust_spread = [&](const std::vector<char>& keep) {
    std::vector<double> deviation;
    for (int k = 0; k < n; ++k)
      if (keep[k]) deviation.push_back(std::fabs(residual[k]));
    if (deviation.empty()) return 0.0;
    std::nth_element(deviation.begin(), deviation.begin() + deviation.size() / 2, deviation.end());
    return 1.4826 * deviation[deviation.size() / 2];
  };
  std::vector<char> keep(n, 1);
  for (int k = 0; k < n; ++k) residual[k] = up[k] - start;
  double spread = robust_spread(keep);
  int inliers = 0;
  for (int k = 0; k < n; ++k) inliers += keep[k] = std::fabs(residual[k]) <= 3 * std::max(spread, sigma[k]);
  Vector6 coef = Vector6::Zero();
  Matrix6 normal = Matrix6::Identity();
  for (int pass = 0; pass < 2; ++pass) {
    if (inliers < min_points) return fit;
    params = !spread_out || inliers < 4 ? 1 : inliers < 12 ? 3 : 6;
    normal.setZero();
    Vector6 rhs = Vector6::Zero();
    for (int k = 0; k < n; ++k) {
      weight[k] = keep[k] ? kernel[k] / (sigma[k] * sigma[k]) : 0;
      const Vector6 a = basis(k);
      normal += weight[k] * a * a.transpose();
      rhs += weight[k] * a * up[k];
    }
    for (int d = params; d < 6; ++d) normal(d, d) = 1;  // unused terms: zero
    coef = normal.ldlt().solve(rhs);
    if (!coef.allFinite()) return fit;
    for (int k = 0; k < n; ++k) residual[k] = up[k] - basis(k).dot(coef);
    if (pass == 1) break;
    spread = robust_spread(keep);
    inliers = 0;
    for (int k = 0; k < n; ++k) inliers += keep[k] = std::fabs(residual[k]) <= 3 * std::max(spread, sigma[k]);
  }
  // The points must surround the centre: a surface extrapolated off one side
  // of them (the swath's edges) is a guess, left a hole.
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  double kernel_sum = 0;
  for (int k = 0; k < n; ++k)
    if (keep[k]) {
      centroid += kernel[k] * Eigen::Vector2d(dx[k], dy[k]);
      kernel_sum += kernel[k];
    }
  if (!(kernel_sum > 0) || (centroid / kernel_sum).norm() > kMaxCentroidOffset) return fit;
  // Sandwich covariance: each point's variance its sigma^2, inflated when the
  // residuals say the points scatter more than their sigmas.
  double chi2 = 0, weight_sum = 0;
  for (int k = 0; k < n; ++k) {
    const double h = weight[k] * sigma[k] * sigma[k];  // the kernel, 0 for a dropped point
    chi2 += h * residual[k] * residual[k] / (sigma[k] * sigma[k]);
    weight_sum += h;
  }
  const double reduced = std::max(1.0, chi2 / weight_sum * inliers / std::max(1, inliers - params));
  Matrix6 meat = Matrix6::Zero();
  for (int k = 0; k < n; ++k) {
    const Vector6 a = basis(k);
    meat += weight[k] * weight[k] * sigma[k] * sigma[k] * reduced * a * a.transpose();
  }
  const Matrix6 bread = normal.inverse();
  // Averaging shrinks the points' noise but not what the local surface cannot
  // follow (relief finer than the cell): the residuals' variance beyond the
  // points' own is added as a bias term, undiminished.
  double excess = 0, kernel_weight = 0;
  for (int k = 0; k < n; ++k)
    if (weight[k] > 0) {
      excess += kernel[k] * (residual[k] * residual[k] - sigma[k] * sigma[k]);
      kernel_weight += kernel[k];
    }
  const double misfit =
      kernel_weight > 0 ? std::max(0.0, excess / kernel_weight) * inliers / std::max(1, inliers - params) : 0.0;
  const double variance = (bread * meat * bread)(0, 0) + misfit;
  std::vector<double> abs_residual;
  for (int k = 0; k < n; ++k)
    if (weight[k] > 0) abs_residual.push_back(std::fabs(residual[k]));
  std::nth_element(abs_residual.begin(), abs_residual.begin() + inliers / 2, abs_residual.end());
  fit.ok = std::isfinite(variance) && variance >= 0;
  fit.height = coef[0];
  fit.sigma = std::sqrt(variance);
  fit.spread = 1.4826 * abs_residual[inliers / 2];
  return fit;
}

// Heights and sigmas of every swath cell from the points not rejected.
void FitGrid(const std::vector<UsablePoint>& points, const std::vector<char>& rejected, const cv::Mat1b& swath,
             const HeightFitOptions& options, HeightGrid* grid, cv::Mat1f* spread) {
  PointIndex index;
  index.Build(points, *grid);
  const double radius_m = options.radius_cells * grid->cell_m;
  const int reach = static_cast<int>(std::ceil(options.radius_cells)) + 1;
  grid->height_m.setTo(kNaN);
  grid->sigma_m.setTo(kNaN);
  spread->create(grid->rows(), grid->cols());
  spread->setTo(kNaN);
  std::vector<int> near;
  for (int r = 0; r < grid->rows(); ++r)
    for (int c = 0; c < grid->cols(); ++c) {
      if (!swath(r, c)) continue;
      const LocalXY centre = grid->CellCentre(r, c);
      near.clear();
      for (int rr = std::max(0, r - reach); rr <= std::min(grid->rows() - 1, r + reach); ++rr)
        for (int cc = std::max(0, c - reach); cc <= std::min(grid->cols() - 1, c + reach); ++cc) {
          const int cell = rr * grid->cols() + cc;
          for (int o = index.start[cell]; o < index.start[cell + 1]; ++o) {
            const int k = index.order[o];
            if (rejected[k]) continue;
            if (std::hypot(points[k].east - centre.east, points[k].north - centre.north) <= radius_m) near.push_back(k);
          }
        }
      const CellFit fit = FitCell(points, near, centre.east, centre.north, radius_m, options.min_points);
      if (!fit.ok || fit.sigma > options.max_sigma_m) continue;
      grid->height_m(r, c) = static_cast<float>(fit.height);
      grid->sigma_m(r, c) = static_cast<float>(fit.sigma);
      (*spread)(r, c) = static_cast<float>(fit.spread);
    }
}

// Fills holes no larger than max_cells that do not reach the swath's edge,
// ring by ring from their rims; the sigma grows by `sigma_per_cell` a ring.
long FillSmallHoles(const cv::Mat1b& swath, long max_cells, double sigma_per_cell, HeightGrid* grid) {
  cv::Mat1b hole(grid->rows(), grid->cols(), uchar(0));
  for (int r = 0; r < grid->rows(); ++r)
    for (int c = 0; c < grid->cols(); ++c) hole(r, c) = swath(r, c) && !std::isfinite(grid->height_m(r, c)) ? 255 : 0;
  cv::Mat1i labels;
  cv::Mat stats, centroids;
  const int count = cv::connectedComponentsWithStats(hole, labels, stats, centroids, 4, CV_32S);
  std::vector<char> fillable(count, 0);
  for (int l = 1; l < count; ++l) fillable[l] = stats.at<int>(l, cv::CC_STAT_AREA) <= max_cells;
  // A hole touching the grid border or a cell outside the swath is open: not filled.
  for (int r = 0; r < grid->rows(); ++r)
    for (int c = 0; c < grid->cols(); ++c) {
      const int l = labels(r, c);
      if (l == 0 || !fillable[l]) continue;
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc;
          if (rr < 0 || cc < 0 || rr >= grid->rows() || cc >= grid->cols() || !swath(rr, cc)) fillable[l] = 0;
        }
    }
  long filled = 0;
  std::vector<std::pair<cv::Point, std::pair<float, float>>> ring;
  while (true) {
    ring.clear();
    for (int r = 0; r < grid->rows(); ++r)
      for (int c = 0; c < grid->cols(); ++c) {
        if (!fillable[labels(r, c)] || labels(r, c) == 0 || std::isfinite(grid->height_m(r, c))) continue;
        double h = 0, s = 0;
        int known = 0;
        for (int dr = -1; dr <= 1; ++dr)
          for (int dc = -1; dc <= 1; ++dc) {
            const int rr = r + dr, cc = c + dc;
            if ((dr == 0 && dc == 0) || rr < 0 || cc < 0 || rr >= grid->rows() || cc >= grid->cols()) continue;
            if (!std::isfinite(grid->height_m(rr, cc))) continue;
            h += grid->height_m(rr, cc);
            s = std::max(s, static_cast<double>(grid->sigma_m(rr, cc)));
            ++known;
          }
        if (known > 0)
          ring.push_back({{c, r}, {static_cast<float>(h / known), static_cast<float>(s + sigma_per_cell)}});
      }
    if (ring.empty()) break;
    for (const auto& [p, v] : ring) {
      grid->height_m(p.y, p.x) = v.first;
      grid->sigma_m(p.y, p.x) = v.second;
    }
    filled += static_cast<long>(ring.size());
  }
  // Ring means favour the rim's nearest side; relax the filled cells to the
  // harmonic surface through the rim (Laplace interpolation).
  std::vector<cv::Point> cells;
  for (int r = 0; r < grid->rows(); ++r)
    for (int c = 0; c < grid->cols(); ++c)
      if (labels(r, c) != 0 && fillable[labels(r, c)]) cells.emplace_back(c, r);
  for (int iteration = 0; iteration < 100 && !cells.empty(); ++iteration)
    for (const cv::Point& p : cells) {
      double sum = 0;
      int known = 0;
      const cv::Point next[4] = {{p.x - 1, p.y}, {p.x + 1, p.y}, {p.x, p.y - 1}, {p.x, p.y + 1}};
      for (const cv::Point& q : next) {
        if (q.x < 0 || q.y < 0 || q.x >= grid->cols() || q.y >= grid->rows()) continue;
        const float h = grid->height_m(q.y, q.x);
        if (std::isfinite(h)) {
          sum += h;
          ++known;
        }
      }
      if (known > 0) grid->height_m(p.y, p.x) = static_cast<float>(sum / known);
    }
  return filled;
}

}  // namespace

void HeightFitOptions::Check() const {
  if (!(cell_m >= 0) || !std::isfinite(cell_m) || cell_m > 1000)
    throw InputError("", 0, "--dem-cell", "expected metres in [0, 1000] (0: from the point density)");
  if (!(gsd_m >= 0) || !std::isfinite(gsd_m)) throw InputError("", 0, "gsd_m", "expected metres >= 0");
  if (!(radius_cells >= 0.5 && radius_cells <= 10)) throw InputError("", 0, "radius_cells", "expected 0.5..10");
  if (min_points < 1 || min_points > 1000) throw InputError("", 0, "min_points", "expected 1..1000");
  if (!(outlier_sigmas > 0) || !std::isfinite(outlier_sigmas))
    throw InputError("", 0, "outlier_sigmas", "expected sigmas > 0");
  if (!(max_fill_m >= 0) || !std::isfinite(max_fill_m)) throw InputError("", 0, "max_fill_m", "expected metres >= 0");
  if (!(max_sigma_m > 0)) throw InputError("", 0, "--dem-max-sigma", "expected metres > 0");
}

HeightGrid FitHeightGrid(const SeabedPoints& points, const std::vector<std::array<LocalXY, 4>>& swath,
                         bool has_depth_datum, const HeightFitOptions& options, HeightFitReport* report) {
  options.Check();
  HeightFitReport rep;
  std::vector<UsablePoint> usable;
  usable.reserve(points.size());
  for (const SeabedPoint& p : points)
    if (p.east_north_up_m.allFinite() && std::isfinite(p.sigma_up_m) && p.sigma_up_m > 0)
      usable.push_back({p.east_north_up_m.x(), p.east_north_up_m.y(), p.east_north_up_m.z(), p.sigma_up_m});
  rep.points = static_cast<long>(usable.size());
  HeightGrid grid;
  grid.has_depth_datum = has_depth_datum;
  if (usable.empty()) {
    if (report) *report = rep;
    return grid;
  }
  // Extent: the swath's, or the points'.
  double e0 = std::numeric_limits<double>::max(), e1 = -e0, n0 = e0, n1 = -e0;
  auto extend = [&](double e, double n) {
    e0 = std::min(e0, e);
    e1 = std::max(e1, e);
    n0 = std::min(n0, n);
    n1 = std::max(n1, n);
  };
  for (const auto& f : swath)
    for (const LocalXY& p : f) extend(p.east, p.north);
  if (swath.empty())
    for (const UsablePoint& p : usable) extend(p.east, p.north);

  double cell = options.cell_m;
  if (cell <= 0) {
    // Density over the area the points occupy (a 0.25 m occupancy grid).
    constexpr double kCoarse = 0.25;
    const int cols = static_cast<int>((e1 - e0) / kCoarse) + 1, rows = static_cast<int>((n1 - n0) / kCoarse) + 1;
    long occupied = 0;
    if (static_cast<double>(cols) * rows < 5e7) {
      std::vector<char> seen(static_cast<size_t>(cols) * rows, 0);
      for (const UsablePoint& p : usable) {
        const int c = static_cast<int>((p.east - e0) / kCoarse), r = static_cast<int>((p.north - n0) / kCoarse);
        if (c < 0 || r < 0 || c >= cols || r >= rows) continue;
        char& s = seen[static_cast<size_t>(r) * cols + c];
        occupied += !s;
        s = 1;
      }
    }
    const double density = usable.size() / std::max(occupied * kCoarse * kCoarse, kCoarse * kCoarse);
    const double radius = std::sqrt(6.0 * options.min_points / (M_PI * density));  // ~24 points within it
    cell = std::clamp(radius / options.radius_cells, std::max(8 * options.gsd_m, 0.005), 2.0);
    cell = std::round(cell / 0.005) * 0.005;
  }
  rep.cell_m = cell;
  grid.cell_m = cell;
  grid.east0_m = std::floor(e0 / cell) * cell;
  grid.north0_m = std::ceil(n1 / cell) * cell;
  const long cols = static_cast<long>(std::ceil((e1 - grid.east0_m) / cell)) + 1;
  const long rows = static_cast<long>(std::ceil((grid.north0_m - n0) / cell)) + 1;
  if (cols * rows > kMaxCells)
    throw InputError("", 0, "--dem-cell",
                     "a " + std::to_string(cell) + " m cell makes a grid of " + std::to_string(cols) + "x" +
                         std::to_string(rows) + " cells; choose a larger cell");
  grid.height_m = cv::Mat1f(static_cast<int>(rows), static_cast<int>(cols), kNaN);
  grid.sigma_m = cv::Mat1f(static_cast<int>(rows), static_cast<int>(cols), kNaN);

  cv::Mat1b in_swath(grid.rows(), grid.cols(), uchar(swath.empty() ? 0 : 0));
  if (swath.empty()) {
    // Where the points are: cells within a radius of one.
    for (const UsablePoint& p : usable) {
      double r = 0, c = 0;
      grid.CellOf({p.east, p.north}, &r, &c);
      const int reach = static_cast<int>(std::ceil(options.radius_cells));
      cv::rectangle(in_swath,
                    cv::Point(static_cast<int>(std::lround(c)) - reach, static_cast<int>(std::lround(r)) - reach),
                    cv::Point(static_cast<int>(std::lround(c)) + reach, static_cast<int>(std::lround(r)) + reach),
                    cv::Scalar(255), cv::FILLED);
    }
  } else {
    constexpr int kShift = 4;  // sub-cell corners
    for (const auto& f : swath) {
      std::vector<cv::Point> corners;
      for (const LocalXY& p : f) {
        double r = 0, c = 0;
        grid.CellOf(p, &r, &c);
        corners.emplace_back(static_cast<int>(std::lround(c * (1 << kShift))),
                             static_cast<int>(std::lround(r * (1 << kShift))));
      }
      cv::fillConvexPoly(in_swath, corners, cv::Scalar(255), cv::LINE_8, kShift);
    }
  }

  // Fit, drop the points far from the surface, fit again.
  std::vector<char> rejected(usable.size(), 0);
  cv::Mat1f spread;
  FitGrid(usable, rejected, in_swath, options, &grid, &spread);
  for (size_t k = 0; k < usable.size(); ++k) {
    double r = 0, c = 0;
    grid.CellOf({usable[k].east, usable[k].north}, &r, &c);
    const int ri = static_cast<int>(std::lround(r)), ci = static_cast<int>(std::lround(c));
    if (ri < 0 || ci < 0 || ri >= grid.rows() || ci >= grid.cols()) continue;
    double h = 0, s = 0;
    if (!grid.Sample({usable[k].east, usable[k].north}, &h, &s)) {
      h = grid.height_m(ri, ci);
      s = grid.sigma_m(ri, ci);
      if (!std::isfinite(h)) continue;
    }
    const double local = std::isfinite(spread(ri, ci)) ? spread(ri, ci) : 0.0;
    const double tolerance =
        options.outlier_sigmas * std::sqrt(usable[k].sigma * usable[k].sigma + s * s + local * local);
    if (std::fabs(usable[k].up - h) > tolerance) {
      rejected[k] = 1;
      ++rep.points_rejected;
    }
  }
  if (rep.points_rejected > 0) FitGrid(usable, rejected, in_swath, options, &grid, &spread);

  // Calibration by hold-out: a grid fitted to four points in five predicts
  // the fifth (nearly the whole grid's density: fewer points would make the
  // floor that of a sparser grid). What their squared residuals hold beyond the points' own variance
  // and that grid's is an error no cell's fit can see (relief finer than a
  // cell, between cell centres): a floor added to every cell's sigma. It is
  // added, not multiplied: a cell fitted from many points has a tiny
  // statistical sigma but the same unseen relief as any other.
  {
    constexpr size_t kHoldOutEvery = 5;
    std::vector<char> held_out = rejected;
    for (size_t k = 1; k < usable.size(); k += kHoldOutEvery) held_out[k] = 1;
    HeightGrid half = grid;
    half.height_m = grid.height_m.clone();
    half.sigma_m = grid.sigma_m.clone();
    cv::Mat1f half_spread;
    FitGrid(usable, held_out, in_swath, options, &half, &half_spread);
    std::vector<std::pair<double, double>> terms;  // (standardised^2, excess^2)
    for (size_t k = 1; k < usable.size(); k += kHoldOutEvery) {
      double h = 0, s = 0;
      if (rejected[k] || !half.Sample({usable[k].east, usable[k].north}, &h, &s)) continue;
      const double r2 = (usable[k].up - h) * (usable[k].up - h), p2 = usable[k].sigma * usable[k].sigma;
      terms.push_back({r2 / (p2 + s * s), r2 - p2 - s * s});
    }
    // The worst 1 % are outliers the fit dropped or should have: not calibration.
    std::sort(terms.begin(), terms.end());
    terms.resize(terms.size() - terms.size() / 100);
    double excess = 0;
    for (const auto& t : terms) excess += t.second;
    if (!terms.empty()) rep.sigma_floor_m = std::sqrt(std::max(0.0, excess / terms.size()));
    const float floor2 = static_cast<float>(rep.sigma_floor_m * rep.sigma_floor_m);
    for (int r = 0; r < grid.rows(); ++r)
      for (int c = 0; c < grid.cols(); ++c)
        if (std::isfinite(grid.sigma_m(r, c)))
          grid.sigma_m(r, c) = std::sqrt(grid.sigma_m(r, c) * grid.sigma_m(r, c) + floor2);
  }

  // Small holes, from their rims; the sigma grows by the grid's slope spread.
  std::vector<double> steps;
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c + 1 < grid.cols(); ++c)
      if (std::isfinite(grid.height_m(r, c)) && std::isfinite(grid.height_m(r, c + 1)))
        steps.push_back(std::fabs(grid.height_m(r, c + 1) - grid.height_m(r, c)));
  double step_rms = 0;
  for (double s : steps) step_rms += s * s;
  step_rms = steps.empty() ? 0 : std::sqrt(step_rms / steps.size());
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) rep.cells_estimated += std::isfinite(grid.height_m(r, c)) ? 1 : 0;
  const long max_fill_cells = static_cast<long>(M_PI / 4 * std::pow(options.max_fill_m / cell, 2));
  rep.cells_filled = FillSmallHoles(in_swath, max_fill_cells, step_rms, &grid);
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      if (!in_swath(r, c)) {
        grid.height_m(r, c) = grid.sigma_m(r, c) = kNaN;
        continue;
      }
      ++rep.cells_swath;
      rep.cells_holes += std::isfinite(grid.height_m(r, c)) ? 0 : 1;
    }
  if (report) *report = rep;
  return grid;
}

void ClipHeightGrid(const std::vector<std::vector<LocalXY>>& swath, HeightGrid* grid, HeightFitReport* report) {
  if (grid->empty()) return;
  cv::Mat1b in_swath(grid->rows(), grid->cols(), uchar(0));
  constexpr int kShift = 4;  // sub-cell corners
  for (const auto& f : swath) {
    std::vector<cv::Point> corners;
    for (const LocalXY& p : f) {
      double r = 0, c = 0;
      grid->CellOf(p, &r, &c);
      corners.emplace_back(static_cast<int>(std::lround(c * (1 << kShift))),
                           static_cast<int>(std::lround(r * (1 << kShift))));
    }
    const std::vector<std::vector<cv::Point>> polygons = {corners};
    cv::fillPoly(in_swath, polygons, cv::Scalar(255), cv::LINE_8, kShift);
  }
  HeightFitReport counted = report ? *report : HeightFitReport();
  counted.cells_swath = counted.cells_holes = 0;
  for (int r = 0; r < grid->rows(); ++r)
    for (int c = 0; c < grid->cols(); ++c) {
      if (!in_swath(r, c)) {
        grid->height_m(r, c) = grid->sigma_m(r, c) = kNaN;
        continue;
      }
      ++counted.cells_swath;
      counted.cells_holes += std::isfinite(grid->height_m(r, c)) ? 0 : 1;
    }
  if (report) *report = counted;
}

}  // namespace seamap
