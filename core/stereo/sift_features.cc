#include "core/stereo/sift_features.h"

#include <algorithm>
#include <numeric>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/enhance/pixel_format.h"
#include "core/util/error.h"

namespace seamap {

void SiftOptions::Check() const {
  if (max_features < 50) throw InputError("", 0, "--max-features", "expected at least 50");
  if (!(contrast_threshold > 0 && contrast_threshold < 1))
    throw InputError("", 0, "--contrast-threshold", "expected a number in (0, 1)");
  if (!(clahe_clip >= 0)) throw InputError("", 0, "--clahe", "expected a number >= 0");
}

ImageFeatures DetectSift(const cv::Mat& image, const SiftOptions& options) {
  cv::Mat gray = ToGray8(options.enhance.empty() ? image : options.enhance.Apply(image));
  if (options.clahe_clip > 0) cv::createCLAHE(options.clahe_clip, {8, 8})->apply(gray, gray);
  auto sift = cv::SIFT::create(options.max_features, 3, options.contrast_threshold, 10, 1.6, CV_8U);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  sift->detectAndCompute(gray, cv::noArray(), keypoints, descriptors);
  std::vector<int> order(keypoints.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return keypoints[a].response > keypoints[b].response; });
  ImageFeatures out;
  out.raw_px.reserve(order.size());
  out.size_px.reserve(order.size());
  out.descriptors.create(static_cast<int>(order.size()), 128, CV_8U);
  for (size_t k = 0; k < order.size(); ++k) {
    const cv::KeyPoint& kp = keypoints[order[k]];
    out.raw_px.emplace_back(kp.pt.x - options.offset_px, kp.pt.y - options.offset_px);
    out.size_px.push_back(kp.size);
    descriptors.row(order[k]).copyTo(out.descriptors.row(static_cast<int>(k)));
  }
  return out;
}

cv::Point2d MeasureSiftOffsetPx(const cv::Mat& image, SiftOptions options) {
  options.offset_px = 0;
  const cv::Mat gray = ToGray8(image);
  const ImageFeatures direct = DetectSift(gray, options);
  std::vector<double> bx, by;
  for (int axis = 0; axis < 2; ++axis) {  // mirrored left-right, then top-bottom
    cv::Mat mirrored;
    cv::flip(gray, mirrored, axis == 0 ? 1 : 0);
    const ImageFeatures flipped = DetectSift(mirrored, options);
    // Mirror positions back and pair each keypoint with the nearest one of
    // similar size within half a pixel.
    std::vector<cv::Point2d> back(flipped.size());
    for (size_t k = 0; k < flipped.size(); ++k)
      back[k] = axis == 0 ? cv::Point2d(gray.cols - 1 - flipped.raw_px[k].x, flipped.raw_px[k].y)
                          : cv::Point2d(flipped.raw_px[k].x, gray.rows - 1 - flipped.raw_px[k].y);
    std::vector<int> by_row(back.size());
    std::iota(by_row.begin(), by_row.end(), 0);
    std::sort(by_row.begin(), by_row.end(), [&](int a, int b) { return back[a].y < back[b].y; });
    for (size_t i = 0; i < direct.size(); ++i) {
      const cv::Point2d p = direct.raw_px[i];
      auto lo =
          std::lower_bound(by_row.begin(), by_row.end(), p.y - 0.5, [&](int k, double y) { return back[k].y < y; });
      int best = -1;
      double best_d2 = 0.25;
      for (auto it = lo; it != by_row.end() && back[*it].y <= p.y + 0.5; ++it) {
        const cv::Point2d d = back[*it] - p;
        if (d.dot(d) < best_d2 && std::abs(flipped.size_px[*it] - direct.size_px[i]) < 0.1 * direct.size_px[i])
          best_d2 = d.dot(d), best = *it;
      }
      if (best < 0) continue;
      if (axis == 0)
        bx.push_back(0.5 * (p.x - back[best].x));
      else
        by.push_back(0.5 * (p.y - back[best].y));
    }
  }
  const auto median = [](std::vector<double> v) {
    if (v.empty()) return 0.0;
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  return {median(bx), median(by)};
}

}  // namespace seamap
