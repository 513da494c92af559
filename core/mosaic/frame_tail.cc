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

}  // namespace

std::array<int64_t, 4> TailBounds(const std::vector<TailPixel>& pixels) {
  if (pixels.empty()) return {0, 0, 0, 0};
  std::array<int64_t, 4> b{pixels[0].x, pixels[0].y, pixels[0].x, pixels[0].y};
  for (const TailPixel& p : pixels) {
    b[0] = std::min(b[0], p.x);
    b[2] = std::max(b[2], p.x);
    b[1] = std::min(b[1], p.y);
    b[3] = std::max(b[3], p.y);
  }
  ++b[2];
  ++b[3];
  return b;
}

WarpedFrame SampleTail(const std::vector<TailPixel>& pixels, const cv::Mat& image) {
  WarpedFrame out;
  const int type = image.channels() == 1 ? CV_8UC1 : CV_8UC3;
  if (pixels.empty()) {
    out.pixels = cv::Mat::zeros(1, 1, type);
    out.weight = cv::Mat::zeros(1, 1, CV_8U);
    out.run_offset.assign(2, 0);
    return out;
  }
  const std::array<int64_t, 4> bounds = TailBounds(pixels);
  out.x0 = out.box_x0 = bounds[0];
  out.y0 = out.box_y0 = bounds[1];
  out.box_width = static_cast<int>(bounds[2] - bounds[0]);
  out.box_height = static_cast<int>(bounds[3] - bounds[1]);
  out.pixels = cv::Mat::zeros(out.box_height, out.box_width, type);
  out.weight = cv::Mat::zeros(out.box_height, out.box_width, CV_8U);
  out.run_offset.assign(out.box_height + 1, 0);
  std::vector<const TailPixel*> order;  // by row, then column, for the runs
  order.reserve(pixels.size());
  for (const TailPixel& p : pixels) order.push_back(&p);
  std::sort(order.begin(), order.end(),
            [](const TailPixel* a, const TailPixel* b) { return a->y != b->y ? a->y < b->y : a->x < b->x; });
  const int max_iu = (image.cols - 1) * 256 - 1, max_iv = (image.rows - 1) * 256 - 1;
  size_t k = 0;
  for (int row = 0; row < out.box_height; ++row) {
    for (; k < order.size() && order[k]->y - out.y0 == row; ++k) {
      const TailPixel& p = *order[k];
      const int col = static_cast<int>(p.x - out.x0);
      uint8_t* px = out.pixels.ptr<uint8_t>(row) + col * image.channels();
      if (image.channels() == 1)
        warp::Sample<1>(image.data, image.step[0], p.u, p.v, max_iu, max_iv, px);
      else
        warp::Sample<3>(image.data, image.step[0], p.u, p.v, max_iu, max_iv, px);
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

WarpedFrame DecodeTail(FrameImage& image, const std::vector<TailPixel>& pixels) {
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
  return SampleTail(pixels, image.RowRanges(ranges));
}

}  // namespace seamap
