#pragma once
// Sharpness by Laplacian variance (seed 004, eqs. 13-18): the variance of the
// 4-neighbour Laplacian of the luma, in 8-bit units so one threshold fits 8-
// and 16-bit frames. Low values mean a blurred or hazy frame.
//
// levels > 0 first halves the frame that many times (cv::pyrDown). Sensor noise
// dominates the Laplacian at full resolution (a noisy hazy frame scores higher
// than a clean sharp one); one level down, haze and blur separate clearly.
#include <opencv2/core.hpp>

namespace seamap {

double LaplacianVariance(const cv::Mat& image, int levels = 0);

}  // namespace seamap
