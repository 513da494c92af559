#include "core/mosaic/frame_warper.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "core/camera/frame_projector.h"
#include "core/geo/web_mercator.h"
#include "core/mosaic/warp_pixels.h"

namespace seamap {
namespace {

using warp::BlockRow;
using warp::ImageShape;
using warp::kLut;
using warp::kMaxCell;
using warp::kMaxRivals;
using warp::RowWeights;
using warp::Sample;
using warp::SampleGray4;
using warp::ToCanvasWeights;

constexpr int kBorderSamples = 16;  // per image edge, to bound curved (distorted) edges

// Points along the raw image border (pixel-edge convention), corners first.
std::vector<cv::Point2d> RawBorder(const CameraModel& c) {
  const double l = -0.5, t = -0.5, r = c.width - 0.5, b = c.height - 0.5;
  std::vector<cv::Point2d> pts{{l, t}, {r, t}, {r, b}, {l, b}};
  for (int i = 1; i < kBorderSamples; ++i) {
    const double f = static_cast<double>(i) / kBorderSamples;
    pts.push_back({l + f * (r - l), t});
    pts.push_back({r, t + f * (b - t)});
    pts.push_back({l + f * (r - l), b});
    pts.push_back({l, t + f * (b - t)});
  }
  return pts;
}

// The whole-pixel box {x0, y0, width, height} around border points.
std::array<int64_t, 4> BoxAround(const std::vector<cv::Point2d>& global) {
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (const auto& p : global) {
    min_x = std::min(min_x, p.x);
    max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y);
    max_y = std::max(max_y, p.y);
  }
  const auto x0 = static_cast<int64_t>(std::floor(min_x)), y0 = static_cast<int64_t>(std::floor(min_y));
  return {x0, y0, static_cast<int64_t>(std::ceil(max_x)) - x0 + 1, static_cast<int64_t>(std::ceil(max_y)) - y0 + 1};
}

}  // namespace

bool PaintsAny(const WarpedFrame& frame, const cv::Rect& roi) {
  if (roi.width <= 0 || roi.height <= 0) return false;
  if (frame.run_offset.empty()) return cv::countNonZero(frame.weight(roi)) > 0;
  for (int y = roi.y; y < roi.y + roi.height; ++y) {
    const uint8_t* w = frame.weight.ptr<uint8_t>(y);
    for (int k = frame.run_offset[y]; k < frame.run_offset[y + 1]; ++k) {
      const int b = std::max(frame.runs[k][0], roi.x), e = std::min(frame.runs[k][1], roi.x + roi.width);
      for (int x = b; x < e; ++x)
        if (w[x]) return true;
    }
  }
  return false;
}

FrameWarper::FrameWarper(const CameraModel& camera, const LocalFrame& frame, int zoom, int tile_size, int channels,
                         double feather_power, double seam_band)
    : camera_(camera),
      frame_(frame),
      zoom_(zoom),
      tile_size_(tile_size),
      channels_(channels),
      feather_power_(feather_power),
      seam_band_(seam_band) {
  border_ = camera.HasDistortion() ? camera.Undistort(RawBorder(camera)) : RawBorder(camera);
  border_.insert(border_.begin() + 4, cv::Point2d(camera.cx, camera.cy));  // after the corners: the centre
  // A point 20 % further from the optical axis than any border point is
  // outside the image; past there the lens polynomial is not trusted (it can
  // fold far-away points back into the image).
  for (const auto& p : border_) {
    const double xn = (p.x - camera.cx) / camera.fx, yn = (p.y - camera.cy) / camera.fy;
    max_r2_ = std::max(max_r2_, xn * xn + yn * yn);
  }
  max_r2_ *= 1.44;
  weight_lut_.resize(kLut);
  for (int i = 0; i < kLut; ++i)
    weight_lut_[i] = static_cast<float>(std::pow(static_cast<double>(i) / (kLut - 1), feather_power));
}

std::optional<std::array<LocalXY, 4>> FrameWarper::GroundCorners(const VehiclePose& pose) const {
  auto h = ImageToGround(camera_, pose);
  if (!h) return std::nullopt;
  std::array<LocalXY, 4> out;
  for (int i = 0; i < 4; ++i) {
    Eigen::Vector3d g = *h * Eigen::Vector3d(border_[i].x, border_[i].y, 1.0);
    if (g.z() <= 0) return std::nullopt;
    out[i] = {g.x() / g.z(), g.y() / g.z()};
  }
  return out;
}

std::optional<std::array<LatLon, 4>> FrameWarper::Footprint(const VehiclePose& pose) const {
  auto corners = GroundCorners(pose);
  if (!corners) return std::nullopt;
  std::array<LatLon, 4> out;
  for (int i = 0; i < 4; ++i) out[i] = frame_.ToLatLon((*corners)[i]);
  return out;
}

std::optional<std::vector<cv::Point2d>> FrameWarper::MapBorder(const VehiclePose& pose, size_t count) const {
  auto h = ImageToGround(camera_, pose);
  if (!h || !SeesSeabed(*h)) return std::nullopt;
  // Seabed metres -> global pixels, through PROJ where the principal point
  // lands and a metre east and north of it, then affine: over a frame the
  // projection departs from its tangent by well under a thousandth of a
  // pixel (tested), and PROJ per border point was 1 % of the build.
  const Eigen::Vector3d centre = *h * Eigen::Vector3d(border_[4].x, border_[4].y, 1.0);
  const LocalXY c{centre.x() / centre.z(), centre.y() / centre.z()};
  auto to_pixel = [&](double east, double north) {
    return LatLonToPixel(frame_.ToLatLon({east, north}), zoom_, tile_size_);
  };
  const GlobalPixel p0 = to_pixel(c.east, c.north), pe = to_pixel(c.east + 1, c.north),
                    pn = to_pixel(c.east, c.north + 1);
  // A pixel's centre is its index; global pixel i spans [i, i+1).
  std::vector<cv::Point2d> global(std::min(count, border_.size()));
  for (size_t i = 0; i < global.size(); ++i) {
    const Eigen::Vector3d g = *h * Eigen::Vector3d(border_[i].x, border_[i].y, 1.0);
    const double de = g.x() / g.z() - c.east, dn = g.y() / g.z() - c.north;
    global[i] = {p0.x + (pe.x - p0.x) * de + (pn.x - p0.x) * dn - 0.5,
                 p0.y + (pe.y - p0.y) * de + (pn.y - p0.y) * dn - 0.5};
  }
  return global;
}

std::optional<FrameWarper::MapOutline> FrameWarper::Outline(const VehiclePose& pose) const {
  auto global = MapBorder(pose);
  if (!global) return std::nullopt;
  return MapOutline{BoxAround(*global), {(*global)[0], (*global)[1], (*global)[2], (*global)[3]}};
}

bool FrameWarper::SeesSeabed(const Eigen::Matrix3d& image_to_ground) const {
  for (const auto& b : border_)
    if ((image_to_ground * Eigen::Vector3d(b.x, b.y, 1.0)).z() <= 0) return false;
  return true;
}

bool FrameWarper::SeesSeabed(const VehiclePose& pose) const {
  auto h = ImageToGround(camera_, pose);
  return h && SeesSeabed(*h);
}

cv::Matx33d FrameWarper::BoxToNormalised(const std::vector<cv::Point2d>& global, int64_t x0, int64_t y0) const {
  // From the four corners: the seabed-to-Web-Mercator step is affine to far
  // below a pixel over a frame. Offsets are taken in double before going to
  // float (global pixels at zoom 25 need 33 bits).
  std::vector<cv::Point2f> src(4), dst(4);
  for (int i = 0; i < 4; ++i) {
    src[i] = cv::Point2f(static_cast<float>(border_[i].x), static_cast<float>(border_[i].y));
    dst[i] = cv::Point2f(static_cast<float>(global[i].x - x0), static_cast<float>(global[i].y - y0));
  }
  cv::Matx33d to_image(cv::getPerspectiveTransform(dst, src));
  return camera_.K().inv() * to_image;
}

namespace {

// One exactly evaluated grid point: raw image positions in this frame and in
// the rivals, each with whether its mapping is trustworthy there (in front of
// the camera, near the image).
struct GridPoint {
  float u = 0, v = 0;
  float ru[kMaxRivals] = {0, 0}, rv[kMaxRivals] = {0, 0};
  bool valid = false;
  bool rival_valid[kMaxRivals] = {false, false};
};

struct Projection {
  float u, v;
  bool valid;
};

// Box pixel -> raw image pixel, through normalised coordinates m and the
// lens distortion.
Projection Project(const cv::Matx33d& m, double x, double y, const CameraModel& c, double max_r2) {
  const double z = m(2, 0) * x + m(2, 1) * y + m(2, 2);
  if (!(z > 1e-12)) return {0, 0, false};
  const double xn = (m(0, 0) * x + m(0, 1) * y + m(0, 2)) / z;
  const double yn = (m(1, 0) * x + m(1, 1) * y + m(1, 2)) / z;
  const double r2 = xn * xn + yn * yn;
  if (!(r2 <= max_r2)) return {0, 0, false};
  const auto& d = c.distortion;
  const double radial = 1 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
  const double xd = xn * radial + 2 * d[2] * xn * yn + d[3] * (r2 + 2 * xn * xn);
  const double yd = yn * radial + d[2] * (r2 + 2 * yn * yn) + 2 * d[3] * xn * yn;
  return {static_cast<float>(c.fx * xd + c.cx), static_cast<float>(c.fy * yd + c.cy), true};
}

// How far (raw pixels) the mapping moves across a block, or along a row
// across a cell, with room to spare.
struct Reach {
  float u = 32, v = 32;
};

// Whether the frame may keep some pixel between a few grid points: not if
// they are all clearly outside its image, nor if one rival clearly sees them
// all, and more centrally ("clearly": by more than the mapping moves between
// them, and by a quarter of the seam). So skipping what this rules out never
// loses a pixel the frame keeps.
class KeepTest {
 public:
  KeepTest(const ImageShape& shape, int rivals, const float* inv_seam)
      : shape_(shape), rivals_(rivals), inv_seam_(inv_seam) {}

  bool MayKeep(std::initializer_list<const GridPoint*> points, const Reach& r) const {
    bool all_outside = true;
    for (const GridPoint* g : points) all_outside = all_outside && (!g->valid || Outside(g->u, g->v, r));
    if (all_outside) return false;
    for (int k = 0; k < rivals_; ++k) {
      bool all_taken = true;
      for (const GridPoint* g : points)
        all_taken = all_taken && g->rival_valid[k] && TakenBy(g->ru[k], g->rv[k], g->u, g->v, k, r);
      if (all_taken) return false;
    }
    return true;
  }

  // This frame's position (u, v) clearly outside its image.
  bool Outside(float u, float v, const Reach& r) const {
    return u < -0.5f - r.u || u > shape_.width - 0.5f + r.u || v < -0.5f - r.v || v > shape_.height - 0.5f + r.v;
  }
  // Rival k, at (ru, rv), clearly sees the pixel this frame sees at (u, v), and more centrally.
  bool TakenBy(float ru, float rv, float u, float v, int k, const Reach& r) const {
    return InsideBy(ru, rv, r) && shape_.Ramp(ru, rv, u, v, inv_seam_[k]) < -0.25f;
  }
  // The same test for the ends of a block row `length` pixels long.
  bool MayKeepRow(const BlockRow& row, float length, const Reach& r) const {
    const float u1 = row.u0 + row.du * length, v1 = row.v0 + row.dv * length;
    if (Outside(row.u0, row.v0, r) && Outside(u1, v1, r)) return false;
    for (int k = 0; k < rivals_; ++k)
      if (row.rival[k] && TakenBy(row.ru0[k], row.rv0[k], row.u0, row.v0, k, r) &&
          TakenBy(row.ru0[k] + row.rdu[k] * length, row.rv0[k] + row.rdv[k] * length, u1, v1, k, r))
        return false;
    return true;
  }

 private:
  bool InsideBy(float u, float v, const Reach& r) const {
    return u > r.u - 0.5f && u < shape_.width - 0.5f - r.u && v > r.v - 0.5f && v < shape_.height - 0.5f - r.v;
  }

  const ImageShape& shape_;
  int rivals_;
  const float* inv_seam_;
};

// Runs of painted pixels per row, [begin, end] inclusive in box columns, in
// increasing order: a frame paints a band and, along its side edges, slivers
// no neighbour sees, so a row's bounding span is mostly empty.
class RowRuns {
 public:
  static constexpr int kMax = 4;        // per row; later runs merge into the last
  static constexpr int kMergeGap = 16;  // closer runs merge
  void Reset(int rows) {
    count_.assign(rows, 0);
    runs_.resize(static_cast<size_t>(rows) * kMax);
  }
  // Pixels [a, b] of row y are painted; a is not left of the row's earlier runs' starts.
  void Add(int y, int a, int b) {
    int& n = count_[y];
    std::array<int, 2>* r = &runs_[static_cast<size_t>(y) * kMax];
    if (n > 0 && (a <= r[n - 1][1] + kMergeGap || n == kMax))
      r[n - 1][1] = std::max(r[n - 1][1], b);
    else
      r[n++] = {a, b};
  }
  int Count(int y) const { return count_[y]; }
  const std::array<int, 2>& Run(int y, int k) const { return runs_[static_cast<size_t>(y) * kMax + k]; }

 private:
  std::vector<int> count_;
  std::vector<std::array<int, 2>> runs_;
};

// Returns the painted runs of this thread's scratch canvas to zero when a
// warp leaves, whether it returns or throws (a frame whose JPEG data breaks
// off, no memory for the result): the thread's next frame starts clean.
class CanvasCleaner {
 public:
  CanvasCleaner(cv::Mat& pixels, cv::Mat& weight, const RowRuns& runs, int height)
      : pixels_(pixels), weight_(weight), runs_(runs), height_(height) {}
  ~CanvasCleaner() {
    const size_t px_size = pixels_.elemSize();
    for (int y = 0; y < height_; ++y)
      for (int k = 0; k < runs_.Count(y); ++k) {
        const int b = runs_.Run(y, k)[0], n = runs_.Run(y, k)[1] - b + 1;
        std::memset(pixels_.ptr<uint8_t>(y) + b * px_size, 0, n * px_size);
        std::memset(weight_.ptr<uint8_t>(y) + b, 0, n);
      }
  }
  CanvasCleaner(const CanvasCleaner&) = delete;
  CanvasCleaner& operator=(const CanvasCleaner&) = delete;

 private:
  cv::Mat& pixels_;
  cv::Mat& weight_;
  const RowRuns& runs_;
  int height_;
};

// The painted runs of a canvas, cut to their bounding box and copied into
// `out` (pixels, weight, runs, origin).
void CopyPainted(const cv::Mat& canvas_pixels, const cv::Mat& canvas_weight, const RowRuns& runs, int height,
                 WarpedFrame* out) {
  int px0 = std::numeric_limits<int>::max(), px1 = -1, py0 = height, py1 = -1;
  for (int y = 0; y < height; ++y) {
    const int n = runs.Count(y);
    if (n == 0) continue;
    px0 = std::min(px0, runs.Run(y, 0)[0]);
    px1 = std::max(px1, runs.Run(y, n - 1)[1]);
    py0 = std::min(py0, y);
    py1 = y;
  }
  if (py1 < 0) px0 = px1 = py0 = py1 = 0;
  const int out_w = px1 - px0 + 1, out_h = py1 - py0 + 1;
  out->x0 += px0;
  out->y0 += py0;
  // Not zero-filled first: each row's runs are copied and the gaps cleared.
  out->pixels.create(out_h, out_w, canvas_pixels.type());
  out->weight.create(out_h, out_w, CV_8U);
  out->run_offset.assign(out_h + 1, 0);
  out->runs.clear();
  const size_t px_size = canvas_pixels.elemSize();
  for (int y = py0; y <= py1; ++y) {
    uint8_t* out_pix = out->pixels.ptr<uint8_t>(y - py0);
    uint8_t* out_wgt = out->weight.ptr<uint8_t>(y - py0);
    int done = 0;  // out columns [0, done) are written
    for (int k = 0; k < runs.Count(y); ++k) {
      const int b = runs.Run(y, k)[0], n = runs.Run(y, k)[1] - b + 1, at = b - px0;
      std::memset(out_pix + done * px_size, 0, (at - done) * px_size);
      std::memset(out_wgt + done, 0, at - done);
      std::memcpy(out_pix + at * px_size, canvas_pixels.ptr<uint8_t>(y) + b * px_size, n * px_size);
      std::memcpy(out_wgt + at, canvas_weight.ptr<uint8_t>(y) + b, n);
      out->runs.push_back({at, at + n});
      done = at + n;
    }
    std::memset(out_pix + done * px_size, 0, (out_w - done) * px_size);
    std::memset(out_wgt + done, 0, out_w - done);
    out->run_offset[y - py0 + 1] = static_cast<int>(out->runs.size());
  }
}

}  // namespace

std::optional<WarpedFrame> FrameWarper::Warp(const cv::Mat& image, const VehiclePose& pose,
                                             const std::vector<VehiclePose>& neighbours) const {
  return Warp([&image](int, int) -> const cv::Mat& { return image; }, pose, neighbours);
}

std::optional<WarpedFrame> FrameWarper::Warp(const RowSource& rows, const VehiclePose& pose,
                                             const std::vector<VehiclePose>& neighbours, std::vector<TailPixel>* tail,
                                             unsigned tail_sides) const {
  auto global = MapBorder(pose);
  if (!global) return std::nullopt;
  WarpedFrame out;
  const std::array<int64_t, 4> box = BoxAround(*global);
  out.x0 = out.box_x0 = box[0];
  out.y0 = out.box_y0 = box[1];
  const int width = out.box_width = static_cast<int>(box[2]);
  const int height = out.box_height = static_cast<int>(box[3]);
  const cv::Matx33d m = BoxToNormalised(*global, out.x0, out.y0);
  const ImageShape shape(camera_);

  // Rivals: the neighbours' mappings in this box, and how far apart the two
  // frames are (the rival's centrality at this frame's centre), which scales
  // the seam so it spans the same share of the spacing at any overlap.
  std::vector<cv::Matx33d> rivals;
  float inv_seam[kMaxRivals] = {1, 1};
  if (seam_band_ > 0) {
    const cv::Point2d centre((*global)[4].x - out.x0, (*global)[4].y - out.y0);
    for (const VehiclePose& n : neighbours) {
      if (rivals.size() == kMaxRivals) break;
      auto g = MapBorder(n, 5);  // the corners and the centre are all a rival needs
      if (!g) continue;
      const cv::Matx33d r = BoxToNormalised(*g, out.x0, out.y0);
      const Projection c = Project(r, centre.x, centre.y, camera_, max_r2_);
      const float spacing = c.valid ? shape.Centrality(c.u, c.v) : 1.0f;
      inv_seam[rivals.size()] = 1.0f / std::max(1e-6f, static_cast<float>(seam_band_) * std::min(spacing, 1.0f));
      rivals.push_back(r);
    }
  }
  const int n_rivals = static_cast<int>(rivals.size());

  const int cell = grid_step_;
  const float inv_cell = 1.0f / cell;
  // The grid: exact values every cell pixels, covering the box. Rivals are
  // only looked at near this frame.
  const int nx = (width + cell - 1) / cell + 1, ny = (height + cell - 1) / cell + 1;
  std::vector<GridPoint> grid(static_cast<size_t>(nx) * ny);
  for (int gy = 0; gy < ny; ++gy) {
    for (int gx = 0; gx < nx; ++gx) {
      const size_t i = static_cast<size_t>(gy) * nx + gx;
      const double x = gx * cell, y = gy * cell;
      GridPoint& g = grid[i];
      const Projection p = Project(m, x, y, camera_, max_r2_);
      g.u = p.u;
      g.v = p.v;
      g.valid = p.valid;
      if (!p.valid || shape.Tent(p.u, p.v) < -0.5f) continue;  // far outside: rivals do not matter
      for (int k = 0; k < n_rivals; ++k) {
        const Projection q = Project(rivals[k], x, y, camera_, max_r2_);
        g.ru[k] = q.u;
        g.rv[k] = q.v;
        g.rival_valid[k] = q.valid;
      }
    }
  }

  // Blocks between grid points worth visiting (see KeepTest).
  Reach block_reach, row_reach;
  {
    const int cx = std::min(nx / 2, nx - 2), cy = std::min(ny / 2, ny - 2);  // a box of one cell has nx = 2
    const GridPoint& g = grid[static_cast<size_t>(cy) * nx + cx];
    const GridPoint& gx1 = grid[static_cast<size_t>(cy) * nx + cx + 1];
    const GridPoint& gy1 = grid[static_cast<size_t>(cy + 1) * nx + cx];
    if (g.valid && gx1.valid && gy1.valid) {
      block_reach = {1.5f * (std::fabs(gx1.u - g.u) + std::fabs(gy1.u - g.u)) + 1,
                     1.5f * (std::fabs(gx1.v - g.v) + std::fabs(gy1.v - g.v)) + 1};
      row_reach = {1.5f * std::fabs(gx1.u - g.u) + 1, 1.5f * std::fabs(gx1.v - g.v) + 1};
    }
  }
  const KeepTest keep(shape, n_rivals, inv_seam);
  struct Block {
    int bx, by;
  };
  thread_local std::vector<Block> blocks;
  blocks.clear();
  for (int by = 0; by + 1 < ny; ++by) {
    for (int bx = 0; bx + 1 < nx; ++bx) {
      const GridPoint* c[4] = {&grid[static_cast<size_t>(by) * nx + bx], &grid[static_cast<size_t>(by) * nx + bx + 1],
                               &grid[static_cast<size_t>(by + 1) * nx + bx],
                               &grid[static_cast<size_t>(by + 1) * nx + bx + 1]};
      if (!c[0]->valid || !c[1]->valid || !c[2]->valid || !c[3]->valid) continue;
      if (keep.MayKeep({c[0], c[1], c[2], c[3]}, block_reach)) blocks.push_back({bx, by});
    }
  }

  if (blocks.empty()) {  // nothing to paint
    out.pixels = cv::Mat::zeros(1, 1, channels_ == 1 ? CV_8UC1 : CV_8UC3);
    out.weight = cv::Mat::zeros(1, 1, CV_8U);
    out.run_offset.assign(2, 0);
    return out;
  }
  // Painting goes to this thread's scratch canvas (zero, and returned to
  // zero after use): the frame's painted part is often a narrow band of its
  // box, and only that part is copied out.
  thread_local cv::Mat scratch_pixels[2], scratch_weight;
  cv::Mat& canvas_pixels = scratch_pixels[channels_ == 1 ? 0 : 1];
  if (canvas_pixels.rows < height || canvas_pixels.cols < width)
    canvas_pixels = cv::Mat::zeros(std::max(height, canvas_pixels.rows), std::max(width, canvas_pixels.cols),
                                   channels_ == 1 ? CV_8UC1 : CV_8UC3);
  if (scratch_weight.rows < height || scratch_weight.cols < width)
    scratch_weight = cv::Mat::zeros(std::max(height, scratch_weight.rows), std::max(width, scratch_weight.cols), CV_8U);
  thread_local RowRuns painted;
  painted.Reset(height);
  const CanvasCleaner cleaner(canvas_pixels, scratch_weight, painted, height);

  // Per block row: positions linear along it (the grid interpolated
  // bilinearly), weights four pixels at a time, then to the canvas. Pixels
  // are sampled afterwards, once it is known which raw rows they need.
  const float* lut = feather_power_ != 1.0 ? weight_lut_.data() : nullptr;
  // A block's left and right edges: u, v, then each rival's u and v at the
  // top corners, and their change down the block.
  struct Edges {
    float left[2 + 2 * kMaxRivals], left_step[2 + 2 * kMaxRivals];
    float right[2 + 2 * kMaxRivals], right_step[2 + 2 * kMaxRivals];
    bool rival[kMaxRivals];
  };
  auto block_edges = [&](const Block& b, Edges& e) {
    const GridPoint& g00 = grid[static_cast<size_t>(b.by) * nx + b.bx];
    const GridPoint& g10 = (&g00)[1];
    const GridPoint& g01 = (&g00)[nx];
    const GridPoint& g11 = (&g00)[nx + 1];
    auto set = [&](int q, float c00, float c10, float c01, float c11) {
      e.left[q] = c00;
      e.left_step[q] = c01 - c00;
      e.right[q] = c10;
      e.right_step[q] = c11 - c10;
    };
    set(0, g00.u, g10.u, g01.u, g11.u);
    set(1, g00.v, g10.v, g01.v, g11.v);
    for (int k = 0; k < kMaxRivals; ++k) {
      e.rival[k] = k < n_rivals && g00.rival_valid[k] && g10.rival_valid[k] && g01.rival_valid[k] && g11.rival_valid[k];
      set(2 + 2 * k, g00.ru[k], g10.ru[k], g01.ru[k], g11.ru[k]);
      set(3 + 2 * k, g00.rv[k], g10.rv[k], g01.rv[k], g11.rv[k]);
      // A rival that sees the whole block less centrally (its ramp is past
      // 1 by a quarter at every corner) leaves every weight as it is.
      if (e.rival[k] && inv_seam[k] <= 100.0f) {  // a vanishing seam is a step: no margin to trust
        bool behind = true;
        for (const GridPoint* g : {&g00, &g10, &g01, &g11})
          behind = behind && shape.Ramp(g->ru[k], g->rv[k], g->u, g->v, inv_seam[k]) >= 1.25f;
        if (behind) e.rival[k] = false;
      }
    }
  };
  // Row j of a block: each quantity linear along it (start + step * i).
  auto block_row = [&](const Edges& e, int j, BlockRow& r) {
    const float fy = j * inv_cell;
    float start[2 + 2 * kMaxRivals], step[2 + 2 * kMaxRivals];
    for (int q = 0; q < 2 + 2 * kMaxRivals; ++q) {
      const float left = e.left[q] + e.left_step[q] * fy, right = e.right[q] + e.right_step[q] * fy;
      start[q] = left;
      step[q] = (right - left) * inv_cell;
    }
    r.u0 = start[0];
    r.du = step[0];
    r.v0 = start[1];
    r.dv = step[1];
    for (int k = 0; k < kMaxRivals; ++k) {
      r.rival[k] = e.rival[k];
      r.ru0[k] = start[2 + 2 * k];
      r.rdu[k] = step[2 + 2 * k];
      r.rv0[k] = start[3 + 2 * k];
      r.rdv[k] = step[3 + 2 * k];
    }
  };
  // Which pixels of each block row are painted (bit i: pixel i) and where
  // the row lies in the raw image, for the tail and sampling passes.
  struct KeptRow {
    uint64_t mask;
    float u0, du, v0, dv;
  };
  thread_local std::vector<KeptRow> kept_rows;
  kept_rows.resize(blocks.size() * cell);  // each block's masks are cleared when it is visited
  float v_min = 1e30f, v_max = -1e30f;
  // With a tail: the lowest and highest raw rows sampled by pixels that
  // cannot be in the lower, resp. upper, tail. u is linear along a row, so
  // its ends tell whether a run of pixels has any at the side edges asked for.
  const auto side_edges = [&](unsigned left, unsigned right) {
    return std::array<float, 2>{tail_sides & left ? kTailEdge : -1e30f,
                                tail_sides & right ? static_cast<float>(camera_.width - 1) - kTailEdge : 1e30f};
  };
  const std::array<float, 2> lower_edges = side_edges(kTailLowerLeft, kTailLowerRight);
  const std::array<float, 2> upper_edges = side_edges(kTailUpperLeft, kTailUpperRight);
  auto at_edge = [](const std::array<float, 2>& e, float u) { return u < e[0] || u > e[1]; };
  auto none_at_edge = [&](float ua, float ub) {
    return std::min(ua, ub) >= std::max(lower_edges[0], upper_edges[0]) &&
           std::max(ua, ub) <= std::min(lower_edges[1], upper_edges[1]);
  };
  float core_v_max = -1e30f, core_v_min = 1e30f;
  alignas(16) float w[kMaxCell + 4];
  const float row_length = static_cast<float>(cell);
  for (size_t bi = 0; bi < blocks.size(); ++bi) {
    const Block& b = blocks[bi];
    const int x0 = b.bx * cell, y0 = b.by * cell;
    const int w_cols = std::min(cell, width - x0), h_rows = std::min(cell, height - y0);
    for (int j = 0; j < cell; ++j) kept_rows[bi * cell + j].mask = 0;
    Edges edges;
    block_edges(b, edges);
    BlockRow r;
    for (int j = 0; j < h_rows; ++j) {
      block_row(edges, j, r);
      // The row's ends, for the same test as the block's: the handover
      // line crosses blocks, leaving some rows to the rivals.
      if (!keep.MayKeepRow(r, row_length, row_reach)) continue;
      RowWeights(shape, r, n_rivals, inv_seam, lut, w_cols, w);
      const uint64_t kept = ToCanvasWeights(w, w_cols, scratch_weight.ptr<uint8_t>(y0 + j) + x0);
      if (!kept) continue;
      const int i0 = __builtin_ctzll(kept), i1 = 63 - __builtin_clzll(kept);
      painted.Add(y0 + j, x0 + i0, x0 + i1);
      // The raw rows sampled: v is linear along the row, so its ends bound it.
      const float va = r.v0 + r.dv * static_cast<float>(i0), vb = r.v0 + r.dv * static_cast<float>(i1);
      v_min = std::min(v_min, std::min(va, vb));
      v_max = std::max(v_max, std::max(va, vb));
      kept_rows[bi * cell + j] = {kept, r.u0, r.du, r.v0, r.dv};
      if (tail) {
        const float ua = r.u0 + r.du * static_cast<float>(i0), ub = r.u0 + r.du * static_cast<float>(i1);
        if (none_at_edge(ua, ub)) {
          core_v_max = std::max(core_v_max, std::max(va, vb));
          core_v_min = std::min(core_v_min, std::min(va, vb));
        } else {
          for (uint64_t m = kept; m; m &= m - 1) {
            const float fi = static_cast<float>(__builtin_ctzll(m));
            const float u = r.u0 + r.du * fi, v = r.v0 + r.dv * fi;
            if (!at_edge(lower_edges, u)) core_v_max = std::max(core_v_max, v);
            if (!at_edge(upper_edges, u)) core_v_min = std::min(core_v_min, v);
          }
        }
      }
    }
  }

  if (tail && (core_v_max > -1e29f || core_v_min < 1e29f)) {
    // Side-edge pixels that need rows below the last one, or above the
    // first one, decoded for the others become the tail; the rows then
    // decoded are what the others need. (Bilinear: a pixel at v samples
    // rows floor(v) and floor(v) + 1; rows are decoded with one to spare.)
    const int last_row = core_v_max > -1e29f ? static_cast<int>(std::ceil(core_v_max)) + 1 : INT_MAX;
    const int first_row = core_v_min < 1e29f ? static_cast<int>(std::floor(core_v_min)) - 1 : INT_MIN;
    auto below = [&](float v) { return static_cast<int>(std::floor(v)) + 1 > last_row; };
    auto above = [&](float v) { return static_cast<int>(std::floor(v)) < first_row; };
    auto in_tail = [&](float u, float v) {
      return (below(v) && at_edge(lower_edges, u)) || (above(v) && at_edge(upper_edges, u));
    };
    v_min = 1e30f;
    v_max = -1e30f;
    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      const Block& b = blocks[bi];
      const int x0 = b.bx * cell, y0 = b.by * cell;
      for (int j = 0; j < cell; ++j) {
        KeptRow& r = kept_rows[bi * cell + j];
        uint64_t& mask = r.mask;
        if (!mask) continue;
        uint8_t* weights = scratch_weight.ptr<uint8_t>(y0 + j) + x0;
        // The row's ends tell whether any pixel can be a tail.
        const float fa = static_cast<float>(__builtin_ctzll(mask)), fb = static_cast<float>(63 - __builtin_clzll(mask));
        const float va = r.v0 + r.dv * fa, vb = r.v0 + r.dv * fb;
        if (none_at_edge(r.u0 + r.du * fa, r.u0 + r.du * fb) ||
            (!below(std::max(va, vb)) && !above(std::min(va, vb)))) {
          v_min = std::min(v_min, std::min(va, vb));
          v_max = std::max(v_max, std::max(va, vb));
          continue;
        }
        for (uint64_t m = mask; m; m &= m - 1) {
          const int i = __builtin_ctzll(m);
          const float fi = static_cast<float>(i);
          const float u = r.u0 + r.du * fi, v = r.v0 + r.dv * fi;
          if (in_tail(u, v)) {
            tail->push_back({out.x0 + x0 + i, out.y0 + y0 + j, u, v, weights[i]});
            weights[i] = 0;
            mask &= ~(uint64_t{1} << i);
          } else {
            v_min = std::min(v_min, v);
            v_max = std::max(v_max, v);
          }
        }
      }
    }
  }
  // Only now is it known which raw rows the kept pixels sample (bilinear:
  // one more below): a frame kept compressed decodes just those.
  if (v_max >= v_min) {
    const cv::Mat* decoded = &rows(static_cast<int>(std::floor(v_min)) - 1, static_cast<int>(std::ceil(v_max)) + 1);
    const uint8_t* data = decoded->ptr<uint8_t>();
    const size_t step = decoded->step[0];
    const int max_iu = (camera_.width - 1) * 256 - 1, max_iv = (camera_.height - 1) * 256 - 1;
    for (size_t bi = 0; bi < blocks.size(); ++bi) {
      const Block& b = blocks[bi];
      const int x0 = b.bx * cell, y0 = b.by * cell;
      for (int j = 0; j < cell; ++j) {
        const KeptRow& r = kept_rows[bi * cell + j];
        uint64_t mask = r.mask;
        if (!mask) continue;
        uint8_t* pix = canvas_pixels.ptr<uint8_t>(y0 + j) + x0 * channels_;
        if (channels_ == 1) {  // four at a time
          SampleGray4(data, step, r.u0, r.du, r.v0, r.dv, max_iu, max_iv, mask, pix);
          continue;
        }
        for (; mask; mask &= mask - 1) {
          const int i = __builtin_ctzll(mask);
          const float fi = static_cast<float>(i);
          Sample<3>(data, step, r.u0 + r.du * fi, r.v0 + r.dv * fi, max_iu, max_iv, pix + 3 * i);
        }
      }
    }
  }

  CopyPainted(canvas_pixels, scratch_weight, painted, height, &out);
  return out;
}

}  // namespace seamap
