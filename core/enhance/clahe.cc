#include "core/enhance/clahe.h"

#include <vector>

#include <opencv2/imgproc.hpp>

#include "core/enhance/param_check.h"
#include "core/enhance/pixel_format.h"

namespace seamap {

void ClaheParams::Validate() const {
  RequireParam(clip_limit > 0.0 && clip_limit <= 1000.0, "clahe.clip_limit", "a value in (0, 1000]", clip_limit);
  RequireParam(tile_grid >= 1 && tile_grid <= 64, "clahe.tile_grid", "a whole number in [1, 64]", tile_grid);
}

cv::Mat ApplyClahe(const cv::Mat& image, const ClaheParams& params) {
  params.Validate();
  RequireSupportedImage(image, "clahe");
  // A fresh CLAHE object per call: cv::CLAHE keeps scratch buffers, so sharing one across threads is unsafe.
  auto clahe = cv::createCLAHE(params.clip_limit, cv::Size(params.tile_grid, params.tile_grid));
  cv::Mat out;
  if (image.channels() == 1) {
    clahe->apply(image, out);
    return out;
  }
  cv::Mat ycrcb;
  cv::cvtColor(image, ycrcb, cv::COLOR_BGR2YCrCb);
  std::vector<cv::Mat> planes;
  cv::split(ycrcb, planes);
  clahe->apply(planes[0], planes[0]);
  cv::merge(planes, ycrcb);
  cv::cvtColor(ycrcb, out, cv::COLOR_YCrCb2BGR);
  return out;
}

}  // namespace seamap
