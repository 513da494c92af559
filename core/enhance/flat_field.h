#pragma once
// Flat-field (vignetting / lamp falloff) correction estimated from the survey's
// own frames: a running mean of heavily blurred, downsampled frames is the
// illumination pattern shared by all photos (the scene averages out, the lamp
// does not). Each frame is divided by that pattern normalised to mean 1.
// Thread-safe: the build calls Apply from several workers at once.
#include <mutex>
#include <vector>

#include <opencv2/core.hpp>

namespace seamap {

struct FlatFieldParams {
  double smooth = 0.1;    // Gaussian sigma as a fraction of the shorter image side
  double max_gain = 4.0;  // correction gain kept within [1/max_gain, max_gain]
  int memory = 500;       // running mean over about this many frames (older ones fade)
  bool learn = true;      // Apply adds each frame to the estimate before correcting it
  int seed_frames = 20;   // frames a caller should pass to Seed before the first Apply (0 = none)
  void Validate() const;  // throws InputError("flatfield.<param>")
};

class FlatField {
 public:
  explicit FlatField(FlatFieldParams params = {});

  const FlatFieldParams& params() const { return params_; }
  int frame_count() const;

  // Adds one frame to the running mean. All frames must share size and channel count.
  void Add(const cv::Mat& frame);
  void Seed(const std::vector<cv::Mat>& frames);
  void Reset();

  // Correction gain at full resolution (CV_32FC1 or CV_32FC3, mean about 1/mean(flat)).
  // Empty when no frame has been added.
  cv::Mat Gain(const cv::Size& size) const;

  // Divides the frame by the normalised flat field (unchanged if none is known yet).
  cv::Mat Correct(const cv::Mat& frame) const;

  // Add (when params.learn) then Correct.
  cv::Mat Apply(const cv::Mat& frame);

 private:
  FlatFieldParams params_;
  mutable std::mutex mutex_;
  cv::Mat mean_;  // low-resolution running mean, CV_32FC(n), in [0, 1]
  cv::Size frame_size_;
  int count_ = 0;
};

}  // namespace seamap
