#pragma once
// A frame placed on the map: its pixels and blending weights over the part
// of the base zoom it paints, and the canvas a warp paints it on.
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace seamap {

struct WarpedFrame {
  // The frame's bounding box at the base zoom (global pixels): what it is over.
  int64_t box_x0 = 0, box_y0 = 0;
  int box_width = 0, box_height = 0;
  // The part it paints (often a band of the box: it hands the rest to its neighbours).
  int64_t x0 = 0, y0 = 0;  // global pixel of pixels(0, 0) at the base zoom
  cv::Mat pixels;          // CV_8UC1 (gray) or CV_8UC3 (BGR)
  cv::Mat weight;          // CV_8UC1, 0 where the frame paints nothing, 1..255 elsewhere
  // Per row y, runs[run_offset[y] .. run_offset[y + 1]) are column ranges
  // [begin, end), in order, outside which weight is 0 (a band and the
  // slivers along the frame's sides leave most of a row empty). A warp
  // always fills them; a frame made by hand may leave run_offset empty, and
  // then every pixel counts, by its weight.
  std::vector<int> run_offset;
  std::vector<std::array<int, 2>> runs;
};

// Whether the frame paints any pixel of `roi` (in its pixels' coordinates):
// only its runs are looked at.
bool PaintsAny(const WarpedFrame& frame, const cv::Rect& roi);

// Where a warp paints: this thread's scratch canvas over the frame's box
// (zero, and returned to zero when the canvas goes, whether the warp returns
// or throws), with the runs of painted pixels per row. Cut() copies the
// painted part out; a frame often paints a narrow band of its box.
class PaintCanvas {
 public:
  PaintCanvas(int width, int height, int channels);
  ~PaintCanvas();
  PaintCanvas(const PaintCanvas&) = delete;
  PaintCanvas& operator=(const PaintCanvas&) = delete;

  uint8_t* Pixels(int y) { return pixels_.ptr<uint8_t>(y); }
  uint8_t* Weights(int y) { return weight_.ptr<uint8_t>(y); }
  // Pixels [a, b] of row y are painted; a is not left of the row's earlier runs' starts.
  void AddRun(int y, int a, int b);
  // The painted part, cut to its bounding box; `x0, y0` is the box's global pixel.
  void CutInto(int64_t x0, int64_t y0, WarpedFrame* out) const;

 private:
  static constexpr int kMaxRuns = 4;    // per row; later runs merge into the last
  static constexpr int kMergeGap = 16;  // closer runs merge
  int Count(int y) const { return run_count_[y]; }
  const std::array<int, 2>& Run(int y, int k) const { return runs_[static_cast<size_t>(y) * kMaxRuns + k]; }

  cv::Mat& pixels_;
  cv::Mat& weight_;
  int height_;
  std::vector<int>& run_count_;
  std::vector<std::array<int, 2>>& runs_;  // [begin, end] inclusive, in box columns
};

}  // namespace seamap
