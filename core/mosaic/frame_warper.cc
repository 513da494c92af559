#include "core/mosaic/frame_warper.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "core/camera/frame_projector.h"
#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

constexpr int kLut = 1024;
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

}  // namespace

FrameWarper::FrameWarper(const CameraModel& camera, const LocalFrame& frame, int zoom,
                         int tile_size, int channels, double feather_power, double seam_band)
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

std::optional<std::vector<cv::Point2d>> FrameWarper::MapBorder(const VehiclePose& pose) const {
  auto h = ImageToGround(camera_, pose);
  if (!h) return std::nullopt;
  // A pixel's centre is its index; global pixel i spans [i, i+1).
  std::vector<cv::Point2d> global(border_.size());
  for (size_t i = 0; i < border_.size(); ++i) {
    Eigen::Vector3d g = *h * Eigen::Vector3d(border_[i].x, border_[i].y, 1.0);
    if (g.z() <= 0) return std::nullopt;
    GlobalPixel px = LatLonToPixel(frame_.ToLatLon({g.x() / g.z(), g.y() / g.z()}), zoom_, tile_size_);
    global[i] = {px.x - 0.5, px.y - 0.5};
  }
  return global;
}

bool FrameWarper::SeesSeabed(const VehiclePose& pose) const { return MapBorder(pose).has_value(); }

cv::Matx33d FrameWarper::BoxToNormalised(const std::vector<cv::Point2d>& global, int64_t x0,
                                         int64_t y0) const {
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

constexpr int kMaxRivals = 2;  // the previous and the next painted frame

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

// Image geometry for the per-pixel tests, in raw pixels.
struct ImageShape {
  float width, height, half_w, half_h, inv_half_w, inv_half_h, centre_u, centre_v;
  explicit ImageShape(const CameraModel& c)
      : width(static_cast<float>(c.width)), height(static_cast<float>(c.height)),
        half_w(c.width / 2.0f), half_h(c.height / 2.0f),
        inv_half_w(2.0f / c.width), inv_half_h(2.0f / c.height),
        centre_u((c.width - 1) / 2.0f), centre_v((c.height - 1) / 2.0f) {}
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
};

// Bilinear sample at fixed-point (8-bit fraction) position, clamped so all
// four neighbours are inside the image (edge pixels replicate).
template <int kChannels>
inline void Sample(const cv::Mat& image, float u, float v, int max_iu, int max_iv, uint8_t* out) {
  int iu = static_cast<int>(u * 256.0f), iv = static_cast<int>(v * 256.0f);
  iu = std::clamp(iu, 0, max_iu);
  iv = std::clamp(iv, 0, max_iv);
  const int fx = iu & 255, fy = iv & 255;
  const uint8_t* r0 = image.ptr<uint8_t>(iv >> 8) + (iu >> 8) * kChannels;
  const uint8_t* r1 = r0 + image.step[0];
  for (int ch = 0; ch < kChannels; ++ch) {
    const int top = r0[ch] * (256 - fx) + r0[ch + kChannels] * fx;
    const int bottom = r1[ch] * (256 - fx) + r1[ch + kChannels] * fx;
    out[ch] = static_cast<uint8_t>((top * (256 - fy) + bottom * fy + 32768) >> 16);
  }
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
    for (const GridPoint* g : points) all_outside = all_outside && Outside(*g, r);
    if (all_outside) return false;
    for (int k = 0; k < rivals_; ++k) {
      bool all_taken = true;
      for (const GridPoint* g : points) all_taken = all_taken && TakenBy(*g, k, r);
      if (all_taken) return false;
    }
    return true;
  }

 private:
  bool InsideBy(float u, float v, const Reach& r) const {
    return u > r.u - 0.5f && u < shape_.width - 0.5f - r.u && v > r.v - 0.5f && v < shape_.height - 0.5f - r.v;
  }
  bool Outside(const GridPoint& g, const Reach& r) const {
    return !g.valid || g.u < -0.5f - r.u || g.u > shape_.width - 0.5f + r.u || g.v < -0.5f - r.v ||
           g.v > shape_.height - 0.5f + r.v;
  }
  bool TakenBy(const GridPoint& g, int k, const Reach& r) const {
    return g.rival_valid[k] && InsideBy(g.ru[k], g.rv[k], r) &&
           (shape_.Centrality(g.ru[k], g.rv[k]) - shape_.Centrality(g.u, g.v)) * inv_seam_[k] + 1.0f < -0.25f;
  }

  const ImageShape& shape_;
  int rivals_;
  const float* inv_seam_;
};

// The painted rows of a canvas, cut to their bounding box and copied into
// `out` (pixels, weight, spans, origin); the canvas is left zero again.
void CopyPainted(cv::Mat& canvas_pixels, cv::Mat& canvas_weight, const std::vector<int>& first,
                 const std::vector<int>& last, WarpedFrame* out) {
  const int height = static_cast<int>(first.size());
  int px0 = std::numeric_limits<int>::max(), px1 = -1, py0 = height, py1 = -1;
  for (int y = 0; y < height; ++y) {
    if (last[y] < 0) continue;
    px0 = std::min(px0, first[y]); px1 = std::max(px1, last[y]);
    py0 = std::min(py0, y); py1 = y;
  }
  if (py1 < 0) px0 = px1 = py0 = py1 = 0;
  const int out_w = px1 - px0 + 1, out_h = py1 - py0 + 1;
  out->x0 += px0;
  out->y0 += py0;
  out->pixels = cv::Mat::zeros(out_h, out_w, canvas_pixels.type());
  out->weight = cv::Mat::zeros(out_h, out_w, CV_8U);
  out->span_begin.assign(out_h, 0);
  out->span_end.assign(out_h, 0);
  const size_t px_size = canvas_pixels.elemSize();
  for (int y = py0; y <= py1; ++y) {
    if (last[y] < 0) continue;
    const int b = first[y], n = last[y] - b + 1;
    uint8_t* pix = canvas_pixels.ptr<uint8_t>(y) + b * px_size;
    uint8_t* wgt = canvas_weight.ptr<uint8_t>(y) + b;
    std::memcpy(out->pixels.ptr<uint8_t>(y - py0) + (b - px0) * px_size, pix, n * px_size);
    std::memcpy(out->weight.ptr<uint8_t>(y - py0) + (b - px0), wgt, n);
    std::memset(pix, 0, n * px_size);
    std::memset(wgt, 0, n);
    out->span_begin[y - py0] = b - px0;
    out->span_end[y - py0] = b - px0 + n;
  }
}

}  // namespace

std::optional<WarpedFrame> FrameWarper::Warp(const cv::Mat& image, const VehiclePose& pose,
                                             const std::vector<VehiclePose>& neighbours) const {
  return Warp([&image](int, int) -> const cv::Mat& { return image; }, pose, neighbours);
}

std::optional<WarpedFrame> FrameWarper::Warp(const RowSource& rows, const VehiclePose& pose,
                                             const std::vector<VehiclePose>& neighbours) const {
  auto global = MapBorder(pose);
  if (!global) return std::nullopt;
  WarpedFrame out;
  for (int i = 0; i < 4; ++i)
    out.footprint[i] = PixelToLatLon({(*global)[i].x + 0.5, (*global)[i].y + 0.5}, zoom_, tile_size_);
  double min_x = 1e300, min_y = 1e300, max_x = -1e300, max_y = -1e300;
  for (const auto& p : *global) {
    min_x = std::min(min_x, p.x); max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y); max_y = std::max(max_y, p.y);
  }
  out.x0 = static_cast<int64_t>(std::floor(min_x));
  out.y0 = static_cast<int64_t>(std::floor(min_y));
  const int width = static_cast<int>(std::ceil(max_x) - out.x0) + 1;
  const int height = static_cast<int>(std::ceil(max_y) - out.y0) + 1;
  out.box_x0 = out.x0;
  out.box_y0 = out.y0;
  out.box_width = width;
  out.box_height = height;
  const cv::Matx33d m = BoxToNormalised(*global, out.x0, out.y0);
  const ImageShape shape(camera_);

  // Rivals: the neighbours' mappings in this box, and how far apart the two
  // frames are (the rival's centrality at this frame's centre), which scales
  // the seam so it spans the same share of the spacing at any overlap.
  std::vector<cv::Matx33d> rivals;
  std::vector<float> seam;
  if (seam_band_ > 0) {
    const cv::Point2d centre((*global)[4].x - out.x0, (*global)[4].y - out.y0);
    for (const VehiclePose& n : neighbours) {
      if (rivals.size() == kMaxRivals) break;
      auto g = MapBorder(n);
      if (!g) continue;
      const cv::Matx33d r = BoxToNormalised(*g, out.x0, out.y0);
      const Projection c = Project(r, centre.x, centre.y, camera_, max_r2_);
      const float spacing = c.valid ? shape.Centrality(c.u, c.v) : 1.0f;
      rivals.push_back(r);
      seam.push_back(std::max(1e-6f, static_cast<float>(seam_band_) * std::min(spacing, 1.0f)));
    }
  }
  const int n_rivals = static_cast<int>(rivals.size());
  float inv_seam[kMaxRivals] = {1, 1};
  for (int k = 0; k < n_rivals; ++k) inv_seam[k] = 1.0f / seam[k];

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
      g.u = p.u; g.v = p.v; g.valid = p.valid;
      if (!p.valid || shape.Tent(p.u, p.v) < -0.5f) continue;  // far outside: rivals do not matter
      for (int k = 0; k < n_rivals; ++k) {
        const Projection q = Project(rivals[k], x, y, camera_, max_r2_);
        g.ru[k] = q.u; g.rv[k] = q.v; g.rival_valid[k] = q.valid;
      }
    }
  }

  // Blocks between grid points worth visiting (see KeepTest); the same test
  // per row and cell below skips the cells the handover line leaves out of
  // a block.
  Reach block_reach, cell_reach;
  {
    const int cx = nx / 2, cy = ny / 2;
    const GridPoint& g = grid[static_cast<size_t>(cy) * nx + cx];
    const GridPoint& gx1 = grid[static_cast<size_t>(cy) * nx + cx + 1];
    const GridPoint& gy1 = grid[static_cast<size_t>(cy + 1) * nx + cx];
    if (g.valid && gx1.valid && gy1.valid) {
      block_reach = {1.5f * (std::fabs(gx1.u - g.u) + std::fabs(gy1.u - g.u)) + 1,
                     1.5f * (std::fabs(gx1.v - g.v) + std::fabs(gy1.v - g.v)) + 1};
      cell_reach = {1.5f * std::fabs(gx1.u - g.u) + 1, 1.5f * std::fabs(gx1.v - g.v) + 1};
    }
  }
  const KeepTest keep(shape, n_rivals, inv_seam);
  std::vector<uint8_t> active(static_cast<size_t>(nx) * ny, 0);
  int bx_min = nx, bx_max = -1, by_min = ny, by_max = -1;
  for (int by = 0; by + 1 < ny; ++by) {
    for (int bx = 0; bx + 1 < nx; ++bx) {
      const GridPoint* c[4] = {&grid[static_cast<size_t>(by) * nx + bx], &grid[static_cast<size_t>(by) * nx + bx + 1],
                               &grid[static_cast<size_t>(by + 1) * nx + bx],
                               &grid[static_cast<size_t>(by + 1) * nx + bx + 1]};
      if (!c[0]->valid || !c[1]->valid || !c[2]->valid || !c[3]->valid) continue;
      if (!keep.MayKeep({c[0], c[1], c[2], c[3]}, block_reach)) continue;
      active[static_cast<size_t>(by) * nx + bx] = 1;
      bx_min = std::min(bx_min, bx); bx_max = std::max(bx_max, bx);
      by_min = std::min(by_min, by); by_max = std::max(by_max, by);
    }
  }

  if (bx_max < 0) {  // nothing to paint
    out.pixels = cv::Mat::zeros(1, 1, channels_ == 1 ? CV_8UC1 : CV_8UC3);
    out.weight = cv::Mat::zeros(1, 1, CV_8U);
    out.span_begin.assign(1, 0);
    out.span_end.assign(1, 0);
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
  std::vector<int> first_painted(height, width), last_painted(height, -1);

  // Per row: interpolate the mappings along each run of active cells,
  // compute the weights in branch-free (vectorised) passes, then sample the
  // frame only where the weight is not zero.
  const int max_iu = (camera_.width - 1) * 256 - 1, max_iv = (camera_.height - 1) * 256 - 1;
  const bool shaped = feather_power_ != 1.0;
  constexpr float kFar = -1e4f;  // a rival position far outside its image: it does not see the pixel
  const size_t padded = static_cast<size_t>(nx) * cell;
  std::vector<float> buffers((2 + 2 * kMaxRivals + 1) * padded);
  float* const pu = buffers.data();
  float* const pv = pu + padded;
  float* const pw = pv + padded;
  float* const qu[kMaxRivals] = {pw + padded, pw + 3 * padded};
  float* const qv[kMaxRivals] = {pw + 2 * padded, pw + 4 * padded};
  const ImageShape sh = shape;  // a local copy: the loops vectorise
  std::vector<GridPoint> row(nx);
  struct Kept {
    int x, y;
    float u, v;
  };
  thread_local std::vector<Kept> kept;
  kept.clear();
  float v_min = 1e30f, v_max = -1e30f;
  for (int y = by_min * cell; y < std::min(height, (by_max + 1) * cell); ++y) {
    const int gy = y / cell;
    const float fy = (y - gy * cell) * inv_cell;
    const GridPoint* a = &grid[static_cast<size_t>(gy) * nx];
    const GridPoint* b = a + nx;
    const uint8_t* block_active = &active[static_cast<size_t>(gy) * nx];
    uint8_t* wgt = scratch_weight.ptr<uint8_t>(y);
    int& first = first_painted[y];
    int& last = last_painted[y];
    // This row's values at the grid columns, and which cells of the active
    // blocks this row still needs (the handover line crosses blocks).
    for (int gx = bx_min; gx <= bx_max + 1; ++gx) {
      GridPoint& r = row[gx];
      r.valid = a[gx].valid && b[gx].valid;
      r.u = a[gx].u + (b[gx].u - a[gx].u) * fy;
      r.v = a[gx].v + (b[gx].v - a[gx].v) * fy;
      for (int k = 0; k < n_rivals; ++k) {
        r.rival_valid[k] = a[gx].rival_valid[k] && b[gx].rival_valid[k];
        r.ru[k] = a[gx].ru[k] + (b[gx].ru[k] - a[gx].ru[k]) * fy;
        r.rv[k] = a[gx].rv[k] + (b[gx].rv[k] - a[gx].rv[k]) * fy;
      }
    }
    for (int run_begin = bx_min; run_begin <= bx_max;) {
      auto needed = [&](int gx) { return block_active[gx] && keep.MayKeep({&row[gx], &row[gx + 1]}, cell_reach); };
      if (!needed(run_begin)) {
        ++run_begin;
        continue;
      }
      int run_end = run_begin + 1;  // needed cells [run_begin, run_end)
      while (run_end <= bx_max && needed(run_end)) ++run_end;
      // Positions along the run, linear within each cell.
      for (int gx = run_begin; gx < run_end; ++gx) {
        const GridPoint& l = row[gx];
        const GridPoint& r = row[gx + 1];
        float* __restrict u = pu + gx * cell;
        float* __restrict v = pv + gx * cell;
        for (int i = 0; i < cell; ++i) {
          u[i] = l.u + (r.u - l.u) * (i * inv_cell);
          v[i] = l.v + (r.v - l.v) * (i * inv_cell);
        }
        for (int k = 0; k < n_rivals; ++k) {
          float* __restrict qu_k = qu[k] + gx * cell;
          float* __restrict qv_k = qv[k] + gx * cell;
          if (!l.rival_valid[k] || !r.rival_valid[k]) {  // untrustworthy there: far from seeing this cell
            std::fill(qu_k, qu_k + cell, kFar);
            std::fill(qv_k, qv_k + cell, kFar);
            continue;
          }
          for (int i = 0; i < cell; ++i) {
            qu_k[i] = l.ru[k] + (r.ru[k] - l.ru[k]) * (i * inv_cell);
            qv_k[i] = l.rv[k] + (r.rv[k] - l.rv[k]) * (i * inv_cell);
          }
        }
      }
      const int x_begin = run_begin * cell, x_end = std::min(width, run_end * cell);
      {
        float* __restrict w = pw;
        const float* __restrict u = pu;
        const float* __restrict v = pv;
        for (int x = x_begin; x < x_end; ++x) w[x] = sh.Tent(u[x], v[x]);
        if (shaped)
          for (int x = x_begin; x < x_end; ++x)
            w[x] = w[x] > 0 ? weight_lut_[static_cast<int>(w[x] * (kLut - 1))] : w[x];
        for (int k = 0; k < n_rivals; ++k) {
          // Where rival k sees the pixel more centrally by more than its
          // seam, the pixel is its; the weight ramps to zero across the seam.
          const float* __restrict ru = qu[k];
          const float* __restrict rv = qv[k];
          const float inv = inv_seam[k];
          for (int x = x_begin; x < x_end; ++x) {
            // The rival must see the pixel by half a pixel: its own,
            // separately interpolated mapping then agrees that it does.
            const float sees = static_cast<float>((ru[x] > 0.0f) & (ru[x] < sh.width - 1.0f) &
                                                  (rv[x] > 0.0f) & (rv[x] < sh.height - 1.0f));
            const float ramp = (sh.Centrality(ru[x], rv[x]) - sh.Centrality(u[x], v[x])) * inv + 1.0f;
            w[x] *= 1.0f + sees * (std::min(std::max(ramp, 0.0f), 1.0f) - 1.0f);
          }
        }
      }
      for (int x = x_begin; x < x_end; ++x) {
        if (!(pw[x] > 0)) continue;
        wgt[x] = static_cast<uint8_t>(1.5f + 254.0f * pw[x]);
        kept.push_back({x, y, pu[x], pv[x]});
        v_min = std::min(v_min, pv[x]);
        v_max = std::max(v_max, pv[x]);
        first = std::min(first, x);
        last = x;
      }
      run_begin = run_end;
    }
  }

  // Only now is it known which raw rows the kept pixels sample (bilinear:
  // one more below): a frame kept compressed decodes just those.
  if (!kept.empty()) {
    const cv::Mat& image = rows(static_cast<int>(std::floor(v_min)) - 1, static_cast<int>(std::ceil(v_max)) + 1);
    for (const Kept& k : kept) {
      uint8_t* pix = canvas_pixels.ptr<uint8_t>(k.y);
      if (channels_ == 1) Sample<1>(image, k.u, k.v, max_iu, max_iv, pix + k.x);
      else Sample<3>(image, k.u, k.v, max_iu, max_iv, pix + 3 * k.x);
    }
  }

  CopyPainted(canvas_pixels, scratch_weight, first_painted, last_painted, &out);
  return out;
}

}  // namespace seamap
