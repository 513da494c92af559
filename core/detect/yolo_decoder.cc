#include "core/detect/yolo_decoder.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {

const char* YoloLayoutName(YoloLayout layout) {
  return layout == YoloLayout::kV5 ? "YOLOv5" : "YOLOv8";
}

YoloLayout RecogniseYoloLayout(const std::vector<int>& shape, int num_classes, const std::string& model,
                               const std::string& names_source) {
  std::string text = "[";
  for (size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  text += "]";
  const std::string expect = "expected YOLOv5 [1, N, " + std::to_string(5 + num_classes) + "] or YOLOv8 [1, " +
                             std::to_string(4 + num_classes) + ", N] for " + std::to_string(num_classes) +
                             " classes (names from " + names_source + ")";
  if (shape.size() != 3 || shape[0] != 1)
    throw InputError(model, 0, "output", "output shape " + text + " is not [1, A, B]: " + expect);
  const bool v5 = shape[2] == 5 + num_classes, v8 = shape[1] == 4 + num_classes;
  if (v5 == v8)  // neither, or ambiguous (N equal to the other count)
    throw InputError(model, 0, "output",
                     "output shape " + text + (v5 ? " fits both layouts: " : " fits neither layout: ") + expect);
  return v5 ? YoloLayout::kV5 : YoloLayout::kV8;
}

std::vector<YoloBox> DecodeYolo(const cv::Mat& output, YoloLayout layout, int num_classes, float min_score,
                                YoloDropped* dropped) {
  ScoreThresholds thresholds;
  thresholds.all = min_score;
  return DecodeYolo(output, layout, num_classes, thresholds, dropped);
}

std::vector<YoloBox> DecodeYolo(const cv::Mat& output, YoloLayout layout, int num_classes,
                                const ScoreThresholds& thresholds, YoloDropped* dropped) {
  const float min_score = thresholds.Lowest();
  YoloDropped local;
  if (!dropped) dropped = &local;
  CV_Assert(output.dims == 3 && output.type() == CV_32F && output.isContinuous());
  const int a = output.size[1], b = output.size[2];
  const float* d = output.ptr<float>();
  std::vector<YoloBox> boxes;
  const int n = layout == YoloLayout::kV5 ? a : b;
  // v5: row i is d[i*b + k]; v8: column i is d[k*b + i].
  const auto at = [&](int i, int k) { return layout == YoloLayout::kV5 ? d[i * b + k] : d[k * b + i]; };
  const int first_class = layout == YoloLayout::kV5 ? 5 : 4;
  for (int i = 0; i < n; ++i) {
    const float obj = layout == YoloLayout::kV5 ? at(i, 4) : 1.0f;
    if (obj < min_score) continue;
    int best = 0;
    float best_p = at(i, first_class);
    for (int c = 1; c < num_classes; ++c) {
      const float p = at(i, first_class + c);
      if (p > best_p) best_p = p, best = c;
    }
    const float score = obj * best_p;
    if (std::isnan(score) || std::isinf(score)) {
      ++dropped->non_finite;
      continue;
    }
    if (!(score >= min_score) || !(score >= thresholds.For(best))) continue;
    const float cx = at(i, 0), cy = at(i, 1), w = at(i, 2), h = at(i, 3);
    const YoloBox box{cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2, score, best};
    if (!std::isfinite(box.x0) || !std::isfinite(box.y0) || !std::isfinite(box.x1) || !std::isfinite(box.y1)) {
      ++dropped->non_finite;  // a clipped inf would be stored as a box of no size at the window's edge
      continue;
    }
    if (!(w > 0 && h > 0)) continue;
    boxes.push_back(box);
  }
  return KeepBestBoxes(std::move(boxes), kMaxYoloCandidates, dropped);
}

std::vector<YoloBox> KeepBestBoxes(std::vector<YoloBox> boxes, size_t max_boxes, YoloDropped* dropped) {
  if (boxes.size() <= max_boxes) return boxes;
  if (dropped) dropped->capped += static_cast<int>(boxes.size() - max_boxes);
  std::vector<size_t> order(boxes.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  const auto better = [&](size_t a, size_t b) {
    return boxes[a].score != boxes[b].score ? boxes[a].score > boxes[b].score : a < b;
  };
  std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(max_boxes), order.end(), better);
  order.resize(max_boxes);
  std::sort(order.begin(), order.end());
  std::vector<YoloBox> kept;
  kept.reserve(max_boxes);
  for (size_t i : order) kept.push_back(boxes[i]);
  return kept;
}

std::vector<YoloBox> NmsPerClass(const std::vector<YoloBox>& boxes, float iou_threshold) {
  std::map<int, std::vector<int>> by_class;
  for (int i = 0; i < static_cast<int>(boxes.size()); ++i) by_class[boxes[i].class_id].push_back(i);
  std::vector<YoloBox> kept;
  for (const auto& [cls, idx] : by_class) {
    std::vector<cv::Rect2d> rects;
    std::vector<float> scores;
    for (int i : idx) {
      const YoloBox& b = boxes[i];
      rects.emplace_back(b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0);
      scores.push_back(b.score);
    }
    std::vector<int> keep;
    cv::dnn::NMSBoxes(rects, scores, 0.0f, iou_threshold, keep);
    std::vector<YoloBox> cls_kept;
    for (int k : keep) cls_kept.push_back(boxes[idx[k]]);
    std::stable_sort(cls_kept.begin(), cls_kept.end(),
                     [](const YoloBox& p, const YoloBox& q) { return p.score > q.score; });
    kept.insert(kept.end(), cls_kept.begin(), cls_kept.end());
  }
  return kept;
}

Letterbox MakeLetterbox(cv::Size image, cv::Size input) {
  Letterbox lb;
  lb.image = image;
  lb.input = input;
  lb.scale = std::min(static_cast<double>(input.width) / image.width, static_cast<double>(input.height) / image.height);
  const int w = static_cast<int>(std::lround(image.width * lb.scale));
  const int h = static_cast<int>(std::lround(image.height * lb.scale));
  lb.pad_x = (input.width - w) / 2;
  lb.pad_y = (input.height - h) / 2;
  return lb;
}

cv::Mat ApplyLetterbox(const cv::Mat& bgr, const Letterbox& lb) {
  const int w = static_cast<int>(std::lround(lb.image.width * lb.scale));
  const int h = static_cast<int>(std::lround(lb.image.height * lb.scale));
  cv::Mat resized;
  if (w == bgr.cols && h == bgr.rows)
    resized = bgr;
  else
    cv::resize(bgr, resized, cv::Size(w, h), 0, 0, lb.scale < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::Mat out(lb.input, bgr.type(), cv::Scalar::all(114));
  resized.copyTo(out(cv::Rect(lb.pad_x, lb.pad_y, w, h)));
  return out;
}

YoloBox UndoLetterbox(const YoloBox& box, const Letterbox& lb) {
  const auto ux = [&](float x) {
    return static_cast<float>(std::clamp((x - lb.pad_x) / lb.scale, 0.0, static_cast<double>(lb.image.width)));
  };
  const auto uy = [&](float y) {
    return static_cast<float>(std::clamp((y - lb.pad_y) / lb.scale, 0.0, static_cast<double>(lb.image.height)));
  };
  YoloBox out = box;
  out.x0 = ux(box.x0), out.x1 = ux(box.x1), out.y0 = uy(box.y0), out.y1 = uy(box.y1);
  return out;
}

}  // namespace seamap
