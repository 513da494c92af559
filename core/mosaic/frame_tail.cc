#include "core/mosaic/frame_tail.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/mosaic/warp_pixels.h"

namespace seamap {
namespace {

// Rows apart by more than this are worth skipping between (the decoder
// skips whole 8- or 16-row block rows).
constexpr float kSplitRows = 32;

// The frame the pixels make, weights and runs set, pixels still zero.
WarpedFrame TailFrame(const std::vector<TailPixel>& pixels, int type) {
  WarpedFrame out;
  if (pixels.empty()) {
    out.pixels = cv::Mat::zeros(1, 1, type);
    out.weight = cv::Mat::zeros(1, 1, CV_8U);
    out.run_offset.assign(2, 0);
    return out;
  }
  std::vector<const TailPixel*> order;  // by row, then column, for the runs
  order.reserve(pixels.size());
  int64_t x1 = pixels[0].x, y1 = pixels[0].y;
  out.x0 = x1;
  out.y0 = y1;
  for (const TailPixel& p : pixels) {
    order.push_back(&p);
    out.x0 = std::min(out.x0, p.x); x1 = std::max(x1, p.x);
    out.y0 = std::min(out.y0, p.y); y1 = std::max(y1, p.y);
  }
  std::sort(order.begin(), order.end(),
            [](const TailPixel* a, const TailPixel* b) { return a->y != b->y ? a->y < b->y : a->x < b->x; });
  out.box_x0 = out.x0;
  out.box_y0 = out.y0;
  out.box_width = static_cast<int>(x1 - out.x0 + 1);
  out.box_height = static_cast<int>(y1 - out.y0 + 1);
  out.pixels = cv::Mat::zeros(out.box_height, out.box_width, type);
  out.weight = cv::Mat::zeros(out.box_height, out.box_width, CV_8U);
  out.run_offset.assign(out.box_height + 1, 0);
  size_t k = 0;
  for (int row = 0; row < out.box_height; ++row) {
    for (; k < order.size() && order[k]->y - out.y0 == row; ++k) {
      const TailPixel& p = *order[k];
      const int col = static_cast<int>(p.x - out.x0);
      out.weight.ptr<uint8_t>(row)[col] = p.weight;
      if (!out.runs.empty() && static_cast<int>(out.runs.size()) > out.run_offset[row] && out.runs.back()[1] == col)
        ++out.runs.back()[1];
      else
        out.runs.push_back({col, col + 1});
    }
    out.run_offset[row + 1] = static_cast<int>(out.runs.size());
  }
  return out;
}

// Samples the pixels into `out` (TailFrame's) from `image`, which has their rows.
void SampleInto(const std::vector<TailPixel>& pixels, const cv::Mat& image, WarpedFrame* out) {
  const int max_iu = (image.cols - 1) * 256 - 1, max_iv = (image.rows - 1) * 256 - 1;
  for (const TailPixel& p : pixels) {
    uint8_t* px = out->pixels.ptr<uint8_t>(static_cast<int>(p.y - out->y0)) + (p.x - out->x0) * image.channels();
    if (image.channels() == 1) warp::Sample<1>(image.data, image.step[0], p.u, p.v, max_iu, max_iv, px);
    else warp::Sample<3>(image.data, image.step[0], p.u, p.v, max_iu, max_iv, px);
  }
}

}  // namespace

WarpedFrame SampleTail(const std::vector<TailPixel>& pixels, const cv::Mat& image) {
  WarpedFrame out = TailFrame(pixels, image.channels() == 1 ? CV_8UC1 : CV_8UC3);
  SampleInto(pixels, image, &out);
  return out;
}

WarpedFrame DecodeTail(FrameImage& image, const std::vector<TailPixel>& pixels) {
  WarpedFrame out = TailFrame(pixels, image.channels() == 1 ? CV_8UC1 : CV_8UC3);
  if (pixels.empty()) return out;
  // An upper and a lower tail lie far apart: the rows between them are
  // skipped without the inverse DCT. (Bilinear: rows floor(v) and below.)
  std::vector<float> v;
  v.reserve(pixels.size());
  for (const TailPixel& p : pixels) v.push_back(p.v);
  std::sort(v.begin(), v.end());
  auto rows = [](float lo, float hi) {
    return std::array<int, 2>{static_cast<int>(std::floor(lo)) - 1, static_cast<int>(std::ceil(hi)) + 1};
  };
  std::vector<std::array<int, 2>> ranges;
  for (size_t i = 1, first = 0; i <= v.size(); ++i)
    if (i == v.size() || v[i] - v[i - 1] > kSplitRows) {
      ranges.push_back(rows(v[first], v[i - 1]));
      first = i;
    }
  // Released again however the decoding ends.
  struct Release {
    FrameImage& image;
    ~Release() { image.ReleasePixels(); }
  } release{image};
  SampleInto(pixels, image.RowRanges(ranges), &out);
  return out;
}

}  // namespace seamap
