#include "core/mosaic/tile_accumulator.h"

#include <algorithm>
#include <cmath>

#include <opencv2/core/hal/intrin.hpp>

namespace seamap {

TileAccumulator::TileAccumulator(int tile_size, int channels, int64_t origin_x, int64_t origin_y)
    : tile_size_(tile_size),
      channels_(channels),
      origin_x_(origin_x),
      origin_y_(origin_y),
      sum_(tile_size, tile_size, CV_32FC(channels), cv::Scalar::all(0)),
      weight_(tile_size, tile_size, CV_32F, cv::Scalar(0)) {}

void TileAccumulator::Seed(const cv::Mat& tile, const cv::Mat& weights) {
  CV_Assert(tile.rows == tile_size_ && tile.cols == tile_size_ && tile.channels() == channels_ + 1);
  const bool known = !weights.empty();
  CV_Assert(!known || (weights.type() == CV_16U && weights.size() == tile.size()));
  for (int y = 0; y < tile_size_; ++y) {
    const uint8_t* src = tile.ptr<uint8_t>(y);
    const uint16_t* kw = known ? weights.ptr<uint16_t>(y) : nullptr;
    float* s = sum_.ptr<float>(y);
    float* w = weight_.ptr<float>(y);
    for (int x = 0; x < tile_size_; ++x, src += channels_ + 1, s += channels_) {
      if (src[channels_] == 0) continue;
      // A covered pixel whose weight rounded to 0 still counts a little.
      const float k = known ? std::max(kw[x], uint16_t{1}) / 256.0f : 1.0f;
      for (int c = 0; c < channels_; ++c) s[c] += k * src[c];
      w[x] += k;
    }
  }
}

void TileAccumulator::Restore(const cv::Mat& sums, const cv::Mat& weight_sums) {
  CV_Assert(sums.type() == sum_.type() && sums.size() == sum_.size());
  CV_Assert(weight_sums.type() == CV_32F && weight_sums.size() == weight_.size());
  sums.copyTo(sum_);
  weight_sums.copyTo(weight_);
}

cv::Mat TileAccumulator::Weights() const {
  cv::Mat out;
  weight_.convertTo(out, CV_16U, 256.0);  // rounds and saturates
  return out;
}

bool TileAccumulator::Blend(const WarpedFrame& frame, int64_t x_shift) {
  const int64_t frame_x0 = frame.x0 + x_shift;
  const int64_t x_begin = std::max(origin_x_, frame_x0);
  const int64_t y_begin = std::max(origin_y_, frame.y0);
  const int64_t x_end = std::min(origin_x_ + tile_size_, frame_x0 + frame.pixels.cols);
  const int64_t y_end = std::min(origin_y_ + tile_size_, frame.y0 + frame.pixels.rows);
  if (x_begin >= x_end || y_begin >= y_end) return false;
  constexpr float kScale = 1.0f / 255.0f;
  const bool has_runs = !frame.run_offset.empty();
  const std::array<int, 2> whole{0, frame.pixels.cols};  // a frame without runs: every pixel
  for (int64_t gy = y_begin; gy < y_end; ++gy) {
    const int fy = static_cast<int>(gy - frame.y0);
    // Only the row's painted runs (the rest has weight 0).
    const std::array<int, 2>* run = has_runs ? frame.runs.data() + frame.run_offset[fy] : &whole;
    const std::array<int, 2>* run_end = has_runs ? frame.runs.data() + frame.run_offset[fy + 1] : &whole + 1;
    for (; run != run_end; ++run) {
      const int64_t row_begin = std::max(x_begin, frame_x0 + (*run)[0]);
      const int64_t row_end = std::min(x_end, frame_x0 + (*run)[1]);
      if (row_begin >= row_end) continue;
      const int n = static_cast<int>(row_end - row_begin);
      const int fx = static_cast<int>(row_begin - frame_x0);
      const uint8_t* src = frame.pixels.ptr<uint8_t>(fy) + fx * channels_;
      const uint8_t* wt = frame.weight.ptr<uint8_t>(fy) + fx;
      const int ty = static_cast<int>(gy - origin_y_);
      const int tx = static_cast<int>(row_begin - origin_x_);
      float* s = sum_.ptr<float>(ty) + tx * channels_;
      float* w = weight_.ptr<float>(ty) + tx;
      if (channels_ == 1) {
        for (int i = 0; i < n; ++i) {
          const float k = wt[i] * kScale;
          s[i] += k * src[i];
          w[i] += k;
        }
      } else {
        for (int i = 0; i < n; ++i) {
          const float k = wt[i] * kScale;
          s[3 * i] += k * src[3 * i];
          s[3 * i + 1] += k * src[3 * i + 1];
          s[3 * i + 2] += k * src[3 * i + 2];
          w[i] += k;
        }
      }
    }
  }
  return true;
}

cv::Mat TileAccumulator::Finalize() const {
  // Sixteen pixels at a time (tiles are 256 or 512 wide): a gray value is
  // sum / weight + 0.5, a colour one sum * (1 / weight) + 0.5 (one division
  // for three channels), capped at 255 and truncated; alpha is 255 where any
  // weight arrived, and uncovered pixels come out 0 with alpha 0.
  CV_Assert(tile_size_ % 16 == 0);
  cv::Mat out(tile_size_, tile_size_, CV_8UC(channels_ + 1));
  const cv::v_float32x4 zero = cv::v_setzero_f32(), one = cv::v_setall_f32(1.0f), half = cv::v_setall_f32(0.5f),
                        top = cv::v_setall_f32(255.0f);
  // Sixteen pixels of one channel to 8 bits: value = sum / weight, or sum * weight when given inverses.
  auto to_u8 = [&](const cv::v_float32x4(&sum)[4], const cv::v_float32x4(&weight)[4], bool inverse) {
    cv::v_int32x4 q[4];
    for (int g = 0; g < 4; ++g) {
      const cv::v_float32x4 ratio = inverse ? sum[g] * weight[g] : sum[g] / weight[g];
      q[g] = cv::v_trunc(cv::v_select(weight[g] > zero, cv::v_min(ratio + half, top), zero));
    }
    return cv::v_pack_u(cv::v_pack(q[0], q[1]), cv::v_pack(q[2], q[3]));
  };
  for (int y = 0; y < tile_size_; ++y) {
    const float* s = sum_.ptr<float>(y);
    const float* w = weight_.ptr<float>(y);
    uint8_t* d = out.ptr<uint8_t>(y);
    for (int x = 0; x < tile_size_; x += 16) {
      cv::v_float32x4 weight[4];
      cv::v_int32x4 covered[4];
      for (int g = 0; g < 4; ++g) {
        weight[g] = cv::v_load(w + x + 4 * g);
        covered[g] = cv::v_reinterpret_as_s32(weight[g] > zero);  // all ones: -1
      }
      const cv::v_uint8x16 alpha =
          cv::v_reinterpret_as_u8(cv::v_pack(cv::v_pack(covered[0], covered[1]), cv::v_pack(covered[2], covered[3])));
      if (channels_ == 1) {
        cv::v_float32x4 gray[4];
        for (int g = 0; g < 4; ++g) gray[g] = cv::v_load(s + x + 4 * g);
        cv::v_store_interleave(d + 2 * x, to_u8(gray, weight, false), alpha);
        continue;
      }
      cv::v_float32x4 blue[4], green[4], red[4], inv[4];
      for (int g = 0; g < 4; ++g) {
        cv::v_load_deinterleave(s + 3 * (x + 4 * g), blue[g], green[g], red[g]);
        inv[g] = cv::v_select(weight[g] > zero, one / weight[g], zero);  // > 0 exactly where covered
      }
      cv::v_store_interleave(d + 4 * x, to_u8(blue, inv, true), to_u8(green, inv, true), to_u8(red, inv, true), alpha);
    }
  }
  return out;
}

}  // namespace seamap
