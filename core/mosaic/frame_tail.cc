#include "core/mosaic/frame_tail.h"

#include <algorithm>
#include <cmath>

#include "core/mosaic/warp_pixels.h"

namespace seamap {

WarpedFrame SampleTail(const std::vector<TailPixel>& pixels, const cv::Mat& image) {
  WarpedFrame out;
  const int type = image.channels() == 1 ? CV_8UC1 : CV_8UC3;
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
  const int max_iu = (image.cols - 1) * 256 - 1, max_iv = (image.rows - 1) * 256 - 1;
  size_t k = 0;
  for (int row = 0; row < out.box_height; ++row) {
    for (; k < order.size() && order[k]->y - out.y0 == row; ++k) {
      const TailPixel& p = *order[k];
      const int col = static_cast<int>(p.x - out.x0);
      uint8_t* px = out.pixels.ptr<uint8_t>(row) + col * image.channels();
      if (image.channels() == 1) warp::Sample<1>(image.data, image.step[0], p.u, p.v, max_iu, max_iv, px);
      else warp::Sample<3>(image.data, image.step[0], p.u, p.v, max_iu, max_iv, px);
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
  float v_min = 1e30f, v_max = -1e30f;
  for (const TailPixel& p : pixels) {
    v_min = std::min(v_min, p.v);
    v_max = std::max(v_max, p.v);
  }
  // Released again however the decoding ends.
  struct Release {
    FrameImage& image;
    ~Release() { image.ReleasePixels(); }
  } release{image};
  return SampleTail(pixels, image.Rows(static_cast<int>(std::floor(v_min)) - 1, static_cast<int>(std::ceil(v_max)) + 1));
}

}  // namespace seamap
