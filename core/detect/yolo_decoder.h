#pragma once
// YOLO outputs to boxes: the YOLOv5 layout [1, N, 5+C] and the YOLOv8 layout
// [1, 4+C, N] (Ultralytics ONNX exports, coordinates in input pixels, scores
// after sigmoid), told apart by the class count; letterboxing of a window to
// the network input and back; class-aware non-maximum suppression.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/detect/score_thresholds.h"

namespace seamap {

enum class YoloLayout { kV5, kV8 };
const char* YoloLayoutName(YoloLayout layout);

// The layout of an output of `shape` for `num_classes` classes. Throws
// InputError(model, 0, "output", ...) quoting the shape, C and
// `names_source` (where the class names came from) when it fits neither.
YoloLayout RecogniseYoloLayout(const std::vector<int>& shape, int num_classes, const std::string& model,
                               const std::string& names_source);

struct YoloBox {
  float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // input pixels, (0,0) = north-west corner of the first pixel
  float score = 0;
  int class_id = 0;
};

// What a window's decoding dropped (issue 33): a model that outputs inf/NaN
// boxes, or proposes more boxes than any window holds objects.
struct YoloDropped {
  int non_finite = 0;  // box or score inf/NaN: never stored
  int capped = 0;      // over kMaxYoloCandidates before NMS or kMaxYoloBoxes after it
};

// At most this many boxes of a window go into NMS (the best scores; a real
// model proposes a few hundred over the score, the shipped one 2100 at all),
// and at most kMaxYoloBoxes come out of it (Ultralytics' max_det).
constexpr int kMaxYoloCandidates = 3000;
constexpr int kMaxYoloBoxes = 300;

// Boxes scoring at least `min_score`, finite, the best kMaxYoloCandidates.
// `output` is the 3-D float blob.
std::vector<YoloBox> DecodeYolo(const cv::Mat& output, YoloLayout layout, int num_classes, float min_score,
                                YoloDropped* dropped = nullptr);
// The same with a threshold per class: a box (of its best class) is kept
// when it reaches its class's threshold.
std::vector<YoloBox> DecodeYolo(const cv::Mat& output, YoloLayout layout, int num_classes,
                                const ScoreThresholds& thresholds, YoloDropped* dropped = nullptr);

// Class-aware NMS (OpenCV 4.6 lacks NMSBoxesBatched: one pass per class).
// Output sorted by class, then descending score.
std::vector<YoloBox> NmsPerClass(const std::vector<YoloBox>& boxes, float iou_threshold);

// The `max_boxes` best scores of `boxes` (ties: the earlier), in their order;
// how many were dropped added to dropped->capped.
std::vector<YoloBox> KeepBestBoxes(std::vector<YoloBox> boxes, size_t max_boxes, YoloDropped* dropped);

// Fits an image into the network input keeping its aspect ratio, padded
// with grey 114 (Ultralytics' letterbox).
struct Letterbox {
  double scale = 1;
  int pad_x = 0, pad_y = 0;
  cv::Size image, input;
};
Letterbox MakeLetterbox(cv::Size image, cv::Size input);
cv::Mat ApplyLetterbox(const cv::Mat& bgr, const Letterbox& lb);
// A box in input pixels back to image pixels, clipped to the image.
YoloBox UndoLetterbox(const YoloBox& box, const Letterbox& lb);

}  // namespace seamap
