#include "core/trajectory/frame_features.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/enhance/pixel_format.h"
#include "core/util/error.h"

namespace seamap {

void FeatureOptions::Check() const {
  if (max_features < 50) throw InputError("", 0, "max_features", "expected at least 50");
  if (max_side_px < 200) throw InputError("", 0, "max_side_px", "expected at least 200 pixels");
  if (!(clahe_clip > 0)) throw InputError("", 0, "clahe_clip", "expected a number > 0");
  if (!(contrast_threshold > 0)) throw InputError("", 0, "contrast_threshold", "expected a number > 0");
}

std::optional<std::string> WhyNoTexture(const cv::Mat& image) {
  if (image.empty()) return std::string("no texture: an empty image");
  cv::Scalar mean, deviation;
  cv::meanStdDev(ToGray8(image), mean, deviation);
  if (deviation[0] >= 1.0) return std::nullopt;
  char text[160];
  std::snprintf(text, sizeof text,
                "no texture: the image is uniform (grey level %.1f, standard deviation %.2f of 255; all black?)",
                mean[0], deviation[0]);
  return std::string(text);
}

bool SameFeatures(const FrameFeatures& a, const FrameFeatures& b) {
  if (a.ideal_px.size() != b.ideal_px.size() || a.descriptors.size() != b.descriptors.size() ||
      a.descriptors.type() != b.descriptors.type())
    return false;
  if (!std::equal(a.ideal_px.begin(), a.ideal_px.end(), b.ideal_px.begin())) return false;
  for (int r = 0; r < a.descriptors.rows; ++r)
    if (std::memcmp(a.descriptors.ptr(r), b.descriptors.ptr(r), a.descriptors.cols * a.descriptors.elemSize()) != 0)
      return false;
  return true;
}

double WorkingScale(const CameraModel& camera, int max_side_px) {
  return std::min(1.0, static_cast<double>(max_side_px) / std::max(camera.width, camera.height));
}

FrameFeatures DetectFeatures(const cv::Mat& image, const CameraModel& camera, const FeatureOptions& options) {
  const double scale = WorkingScale(camera, options.max_side_px);
  const cv::Size working(static_cast<int>(std::lround(camera.width * scale)),
                         static_cast<int>(std::lround(camera.height * scale)));
  const cv::Size detected =
      options.skip_upsampled_octave ? cv::Size((working.width + 1) / 2, (working.height + 1) / 2) : working;
  cv::Mat gray = ToGray8(options.enhance.empty() ? image : options.enhance.Apply(image));
  if (gray.size() != detected) cv::resize(gray, gray, detected, 0, 0, cv::INTER_AREA);
  // Pixel centres at integers: full-resolution x = (x_d + 0.5) / s - 0.5 (and
  // likewise for a frame of another size that was scaled to the camera's).
  const double sx = static_cast<double>(detected.width) / camera.width;
  const double sy = static_cast<double>(detected.height) / camera.height;

  FrameFeatures out;
  std::vector<cv::KeyPoint> keypoints;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const bool relaxed = attempt == 1;
    cv::Mat equalised;
    cv::createCLAHE(relaxed ? std::max(4.0, options.clahe_clip) : options.clahe_clip, {8, 8})->apply(gray, equalised);
    auto sift =
        cv::SIFT::create(options.max_features, 3, options.contrast_threshold * (relaxed ? 0.5 : 1.0), 10, 1.6, CV_8U);
    keypoints.clear();
    out.descriptors.release();
    sift->detectAndCompute(equalised, cv::noArray(), keypoints, out.descriptors);
    out.relaxed = relaxed;
    if (static_cast<int>(keypoints.size()) >= options.min_keypoints) break;
  }
  // Strongest first: registration seeds its search with the first ones.
  std::vector<int> order(keypoints.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return keypoints[a].response > keypoints[b].response; });
  cv::Mat sorted(out.descriptors.rows, out.descriptors.cols, out.descriptors.type());
  std::vector<cv::Point2d> raw(keypoints.size());
  for (size_t k = 0; k < order.size(); ++k) {
    const cv::KeyPoint& kp = keypoints[order[k]];
    raw[k] = {(kp.pt.x + 0.5) / sx - 0.5, (kp.pt.y + 0.5) / sy - 0.5};
    out.descriptors.row(order[k]).copyTo(sorted.row(static_cast<int>(k)));
  }
  out.descriptors = sorted;
  const std::vector<cv::Point2d> ideal = camera.HasDistortion() ? camera.Undistort(raw) : raw;
  out.ideal_px.resize(ideal.size());
  for (size_t k = 0; k < ideal.size(); ++k) out.ideal_px[k] = cv::Point2f(ideal[k]);
  return out;
}

}  // namespace seamap
