#pragma once
// Edge-preserving guided filter (He et al. 2010) built from box filters, used to
// refine the dehazing transmission. ximgproc is not a build dependency.
#include <opencv2/core.hpp>

namespace seamap {

// guide, src: single-channel CV_32F of the same size; radius >= 1, eps > 0.
// subsample > 1 computes the linear coefficients on a 1/subsample grid and
// upsamples them (the "fast guided filter", He & Sun 2015): same result for
// smooth inputs such as a transmission map, at a fraction of the cost.
cv::Mat GuidedFilter(const cv::Mat& guide, const cv::Mat& src, int radius, double eps, int subsample = 1);

}  // namespace seamap
