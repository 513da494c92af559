#include "core/enhance/flat_field.h"

#include <algorithm>
#include <string>

#include <opencv2/imgproc.hpp>

#include "core/enhance/param_check.h"
#include "core/enhance/pixel_format.h"
#include "core/util/error.h"

namespace seamap {
namespace {
constexpr double kWorkSide = 64.0;  // the pattern is smooth: 64 px on the shorter side is plenty

std::string SizeText(const cv::Size& s, int channels) {
  return std::to_string(s.width) + "x" + std::to_string(s.height) + "x" + std::to_string(channels);
}
}  // namespace

void FlatFieldParams::Validate() const {
  RequireParam(smooth > 0.0 && smooth <= 1.0, "flatfield.smooth", "a value in (0, 1]", smooth);
  RequireParam(max_gain >= 1.0 && max_gain <= 100.0, "flatfield.max_gain", "a value in [1, 100]", max_gain);
  RequireParam(memory >= 1, "flatfield.memory", "a whole number >= 1", memory);
  RequireParam(seed_frames >= 0, "flatfield.seed_frames", "a whole number >= 0", seed_frames);
}

FlatField::FlatField(FlatFieldParams params) : params_(params) {
  params_.Validate();
}

int FlatField::frame_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return count_;
}

void FlatField::Add(const cv::Mat& frame) {
  RequireSupportedImage(frame, "flatfield");
  // The expensive part (downsample + blur) runs outside the lock.
  const double scale = kWorkSide / std::min(frame.cols, frame.rows);
  cv::Size work(std::max(1, cvRound(frame.cols * scale)), std::max(1, cvRound(frame.rows * scale)));
  cv::Mat small;
  cv::resize(ToUnitFloat(frame), small, work, 0, 0, cv::INTER_AREA);
  cv::GaussianBlur(small, small, cv::Size(), params_.smooth * kWorkSide, 0, cv::BORDER_REFLECT);

  std::lock_guard<std::mutex> lock(mutex_);
  if (count_ == 0) {
    mean_ = small;
    frame_size_ = frame.size();
    count_ = 1;
    return;
  }
  if (frame.size() != frame_size_ || frame.channels() != mean_.channels())
    throw InputError("", 0, "flatfield",
                     "all frames must share one size and channel count: expected " +
                         SizeText(frame_size_, mean_.channels()) + ", got " + SizeText(frame.size(), frame.channels()));
  ++count_;
  const double weight = 1.0 / std::min(count_, params_.memory);
  cv::addWeighted(mean_, 1.0 - weight, small, weight, 0.0, mean_);
}

void FlatField::Seed(const std::vector<cv::Mat>& frames) {
  for (const cv::Mat& f : frames) Add(f);
}

void FlatField::Reset() {
  std::lock_guard<std::mutex> lock(mutex_);
  mean_.release();
  count_ = 0;
}

cv::Mat FlatField::Gain(const cv::Size& size) const {
  cv::Mat flat;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (count_ == 0) return {};
    if (size != frame_size_)
      throw InputError("", 0, "flatfield",
                       "all frames must share one size: expected " + SizeText(frame_size_, mean_.channels()) +
                           ", got " + SizeText(size, mean_.channels()));
    flat = mean_.clone();
  }
  // Normalise each channel to mean 1 so the correction keeps overall brightness and colour.
  cv::Scalar mean = cv::mean(flat);
  cv::Scalar inv;
  for (int c = 0; c < flat.channels(); ++c) inv[c] = mean[c] > 1e-6 ? 1.0 / mean[c] : 0.0;
  cv::multiply(flat, inv, flat);
  cv::Mat gain;
  cv::max(flat, 1.0 / params_.max_gain, flat);
  cv::divide(1.0, flat, gain);
  cv::min(gain, params_.max_gain, gain);
  cv::resize(gain, gain, size, 0, 0, cv::INTER_LINEAR);
  return gain;
}

cv::Mat FlatField::Correct(const cv::Mat& frame) const {
  RequireSupportedImage(frame, "flatfield");
  cv::Mat gain = Gain(frame.size());
  if (gain.empty()) return frame.clone();
  if (gain.channels() != frame.channels())
    throw InputError("", 0, "flatfield",
                     "expected frames with " + std::to_string(gain.channels()) + " channel(s) like the first, got " +
                         std::to_string(frame.channels()));
  cv::Mat out;
  cv::multiply(frame, gain, out, 1.0, frame.type());  // saturating
  return out;
}

cv::Mat FlatField::Apply(const cv::Mat& frame) {
  if (params_.learn) Add(frame);
  return Correct(frame);
}

}  // namespace seamap
