#pragma once
// One base-zoom tile being painted: a running weighted sum of every frame
// that touched it, so overlaps blend by feather weight instead of the seed's
// hard overwrite. Finalised to 8-bit colour plus alpha (255 where any frame
// contributed, 0 elsewhere).
#include <cstdint>

#include <opencv2/core.hpp>

#include "core/mosaic/warped_frame.h"

namespace seamap {

class TileAccumulator {
 public:
  TileAccumulator(int tile_size, int channels, int64_t origin_x, int64_t origin_y);

  // Continues from a tile written earlier (CV_8UC2 / CV_8UC4 with alpha)
  // with the weights it had (from Weights()), or, when those are no longer
  // known (empty), with each covered pixel as one full-weight observation.
  void Seed(const cv::Mat& tile, const cv::Mat& weights = cv::Mat());

  // The accumulated weight per pixel, CV_16U in 1/256 units (saturating):
  // kept for finished tiles so that a tile painted again after it was
  // written blends with what it had, not as if one frame had made it.
  cv::Mat Weights() const;

  // Adds the part of `frame` that overlaps this tile, the frame's columns
  // moved by x_shift global pixels (a world's width, across the
  // antimeridian). Returns true if it overlapped.
  bool Blend(const WarpedFrame& frame, int64_t x_shift = 0);

  // Whether any frame has painted global pixel (x, y) of this tile.
  bool Covers(int64_t x, int64_t y) const {
    return weight_.at<float>(static_cast<int>(y - origin_y_), static_cast<int>(x - origin_x_)) > 0;
  }

  // CV_8UC2 (gray, alpha) or CV_8UC4 (BGRA).
  cv::Mat Finalize() const;

  // The running sums exactly as they are (a build's checkpoint), and back:
  // a tile continued from them blends on as if it had never stopped.
  const cv::Mat& sums() const { return sum_; }
  const cv::Mat& weight_sums() const { return weight_; }
  void Restore(const cv::Mat& sums, const cv::Mat& weight_sums);

  size_t Bytes() const { return sum_.total() * sum_.elemSize() + weight_.total() * weight_.elemSize(); }

 private:
  int tile_size_, channels_;
  int64_t origin_x_, origin_y_;  // global pixel of the tile's top-left pixel
  cv::Mat sum_;                  // CV_32FC(channels): sum of weight * value
  cv::Mat weight_;               // CV_32F: sum of weights
};

}  // namespace seamap
