#pragma once
// Contrast-limited adaptive histogram equalisation (the "AHE" step of seed 004).
// Colour images are equalised on luma only (YCrCb), so hues are kept.
#include <opencv2/core.hpp>

namespace seamap {

struct ClaheParams {
  double clip_limit = 2.0;  // histogram clip, in multiples of the mean bin count
  int tile_grid = 8;        // tiles per image side
  void Validate() const;    // throws InputError("clahe.<param>")
};

cv::Mat ApplyClahe(const cv::Mat& image, const ClaheParams& params);

}  // namespace seamap
