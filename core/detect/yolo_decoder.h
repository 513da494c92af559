#pragma once
// YOLO outputs to boxes: the YOLOv5 layout [1, N, 5+C] and the YOLOv8 layout
// [1, 4+C, N] (Ultralytics ONNX exports, coordinates in input pixels, scores
// after sigmoid), told apart by the class count; letterboxing of a window to
// the network input and back; class-aware non-maximum suppression.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

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

// Boxes scoring at least `min_score`. `output` is the 3-D float blob.
std::vector<YoloBox> DecodeYolo(const cv::Mat& output, YoloLayout layout, int num_classes, float min_score);

// Class-aware NMS (OpenCV 4.6 lacks NMSBoxesBatched: one pass per class).
// Output sorted by class, then descending score.
std::vector<YoloBox> NmsPerClass(const std::vector<YoloBox>& boxes, float iou_threshold);

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
