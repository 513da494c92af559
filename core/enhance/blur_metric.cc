#include "core/enhance/blur_metric.h"

#include <opencv2/imgproc.hpp>

#include "core/enhance/param_check.h"
#include "core/enhance/pixel_format.h"

namespace seamap {

double LaplacianVariance(const cv::Mat& image, int levels) {
  RequireSupportedImage(image, "blur_metric");
  RequireParam(levels >= 0 && levels <= 8, "blur_metric.levels", "a whole number in [0, 8]", levels);
  cv::Mat gray = image;
  if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  for (int i = 0; i < levels && gray.cols > 8 && gray.rows > 8; ++i) cv::pyrDown(gray, gray);
  cv::Mat lap;
  // ksize 1 is exactly the kernel of eq. 18; scale maps 16-bit values to 8-bit units.
  cv::Laplacian(gray, lap, CV_32F, 1, 255.0 / FullScale(image));
  cv::Scalar mean, dev;
  cv::meanStdDev(lap, mean, dev);
  return dev[0] * dev[0];
}

}  // namespace seamap
