#include "core/mosaic/warped_frame.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace seamap {
namespace {

// One canvas per thread and kind, kept between warps: allocating and zeroing
// a frame's box for every warp cost more than painting its band.
struct Scratch {
  cv::Mat pixels[2];  // gray, colour
  cv::Mat weight;
  std::vector<int> run_count;
  std::vector<std::array<int, 2>> runs;
};
thread_local Scratch scratch;

cv::Mat& Grown(cv::Mat& m, int width, int height, int type) {
  if (m.rows < height || m.cols < width) m = cv::Mat::zeros(std::max(height, m.rows), std::max(width, m.cols), type);
  return m;
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

PaintCanvas::PaintCanvas(int width, int height, int channels)
    : pixels_(Grown(scratch.pixels[channels == 1 ? 0 : 1], width, height, channels == 1 ? CV_8UC1 : CV_8UC3)),
      weight_(Grown(scratch.weight, width, height, CV_8U)),
      height_(height),
      run_count_(scratch.run_count),
      runs_(scratch.runs) {
  run_count_.assign(height, 0);
  runs_.resize(static_cast<size_t>(height) * kMaxRuns);
}

PaintCanvas::~PaintCanvas() {
  const size_t px_size = pixels_.elemSize();
  for (int y = 0; y < height_; ++y)
    for (int k = 0; k < Count(y); ++k) {
      const int b = Run(y, k)[0], n = Run(y, k)[1] - b + 1;
      std::memset(pixels_.ptr<uint8_t>(y) + b * px_size, 0, n * px_size);
      std::memset(weight_.ptr<uint8_t>(y) + b, 0, n);
    }
}

void PaintCanvas::AddRun(int y, int a, int b) {
  int& n = run_count_[y];
  std::array<int, 2>* r = &runs_[static_cast<size_t>(y) * kMaxRuns];
  if (n > 0 && (a <= r[n - 1][1] + kMergeGap || n == kMaxRuns))
    r[n - 1][1] = std::max(r[n - 1][1], b);
  else
    r[n++] = {a, b};
}

void PaintCanvas::CutInto(int64_t x0, int64_t y0, WarpedFrame* out) const {
  int px0 = std::numeric_limits<int>::max(), px1 = -1, py0 = height_, py1 = -1;
  for (int y = 0; y < height_; ++y) {
    const int n = Count(y);
    if (n == 0) continue;
    px0 = std::min(px0, Run(y, 0)[0]);
    px1 = std::max(px1, Run(y, n - 1)[1]);
    py0 = std::min(py0, y);
    py1 = y;
  }
  if (py1 < 0) px0 = px1 = py0 = py1 = 0;  // nothing painted: one empty pixel
  const int out_w = px1 - px0 + 1, out_h = py1 - py0 + 1;
  out->x0 = x0 + px0;
  out->y0 = y0 + py0;
  // Not zero-filled first: each row's runs are copied and the gaps cleared.
  out->pixels.create(out_h, out_w, pixels_.type());
  out->weight.create(out_h, out_w, CV_8U);
  out->run_offset.assign(out_h + 1, 0);
  out->runs.clear();
  const size_t px_size = pixels_.elemSize();
  for (int y = py0; y <= py1; ++y) {
    uint8_t* out_pix = out->pixels.ptr<uint8_t>(y - py0);
    uint8_t* out_wgt = out->weight.ptr<uint8_t>(y - py0);
    int done = 0;  // out columns [0, done) are written
    for (int k = 0; k < Count(y); ++k) {
      const int b = Run(y, k)[0], n = Run(y, k)[1] - b + 1, at = b - px0;
      std::memset(out_pix + done * px_size, 0, (at - done) * px_size);
      std::memset(out_wgt + done, 0, at - done);
      std::memcpy(out_pix + at * px_size, pixels_.ptr<uint8_t>(y) + b * px_size, n * px_size);
      std::memcpy(out_wgt + at, weight_.ptr<uint8_t>(y) + b, n);
      out->runs.push_back({at, at + n});
      done = at + n;
    }
    std::memset(out_pix + done * px_size, 0, (out_w - done) * px_size);
    std::memset(out_wgt + done, 0, out_w - done);
    out->run_offset[y - py0 + 1] = static_cast<int>(out->runs.size());
  }
}

}  // namespace seamap
