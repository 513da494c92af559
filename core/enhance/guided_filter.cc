#include "core/enhance/guided_filter.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace seamap {
namespace {
cv::Mat BoxMean(const cv::Mat& m, int radius) {
  cv::Mat out;
  cv::blur(m, out, cv::Size(2 * radius + 1, 2 * radius + 1), cv::Point(-1, -1), cv::BORDER_REFLECT);
  return out;
}
}  // namespace

cv::Mat GuidedFilter(const cv::Mat& guide, const cv::Mat& src, int radius, double eps, int subsample) {
  CV_Assert(guide.type() == CV_32FC1 && src.type() == CV_32FC1 && guide.size() == src.size());
  CV_Assert(radius >= 1 && eps > 0 && subsample >= 1);
  cv::Mat g = guide, p = src;
  int r = radius;
  if (subsample > 1) {
    cv::Size small(std::max(1, guide.cols / subsample), std::max(1, guide.rows / subsample));
    cv::resize(guide, g, small, 0, 0, cv::INTER_AREA);
    cv::resize(src, p, small, 0, 0, cv::INTER_AREA);
    r = std::max(1, radius / subsample);
  }
  cv::Mat mean_i = BoxMean(g, r);
  cv::Mat mean_p = BoxMean(p, r);
  cv::Mat cov_ip = BoxMean(g.mul(p), r) - mean_i.mul(mean_p);
  cv::Mat var_i = BoxMean(g.mul(g), r) - mean_i.mul(mean_i);
  cv::Mat a = cov_ip / (var_i + eps);
  cv::Mat b = mean_p - a.mul(mean_i);
  cv::Mat mean_a = BoxMean(a, r), mean_b = BoxMean(b, r);
  if (subsample > 1) {
    cv::resize(mean_a, mean_a, guide.size(), 0, 0, cv::INTER_LINEAR);
    cv::resize(mean_b, mean_b, guide.size(), 0, 0, cv::INTER_LINEAR);
  }
  return mean_a.mul(guide) + mean_b;
}

}  // namespace seamap
