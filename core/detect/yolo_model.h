#pragma once
// A YOLO detector exported to ONNX, run with OpenCV DNN on the CPU. Loading
// checks everything a search needs (ONNX file, class names, input size, a
// dry-run forward that yields the output layout) before any tile is read.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

#include "core/detect/yolo_decoder.h"

namespace seamap {

// The lowest minimum score a search takes (--min-score, seamap.min_score):
// below it a model's scores are no probability it could mean, and every
// proposal of every window becomes an object.
constexpr double kMinScoreFloor = 1e-3;

struct YoloModelInfo {
  std::string path;
  std::string name;  // file name#first 16 hex of FNV-1a 64 of its bytes
  std::vector<std::string> class_names;
  std::string names_source;             // "--classes FILE" or "PATH metadata 'names'"
  std::vector<double> class_sizes_m;    // per class, 0 = unknown (metadata seamap.class_sizes_m)
  std::string layer;                    // metadata seamap.layer ("" = not said)
  float min_score = 0.4f;               // metadata seamap.min_score: the score it was validated at, else 0.4
  std::vector<float> class_min_scores;  // metadata seamap.class_min_scores, by class id; empty = min_score for all
  cv::Size input{640, 640};
  YoloLayout layout = YoloLayout::kV8;
  std::vector<int> output_shape;
};

class YoloModel {
 public:
  // classes_path: "" = names from the model's metadata. Throws InputError
  // naming the file (or --classes) on any problem.
  static std::shared_ptr<const YoloModelInfo> Inspect(const std::string& path, const std::string& classes_path);
  explicit YoloModel(std::shared_ptr<const YoloModelInfo> info);

  const YoloModelInfo& info() const { return *info_; }
  // Boxes in image pixels after letterbox undo and per-class NMS, at most
  // kMaxYoloBoxes (the best); what was dropped added to *dropped. image:
  // 8-bit BGR. Not thread-safe: one model per thread.
  std::vector<YoloBox> Detect(const cv::Mat& bgr, float min_score, float nms_iou = 0.5f,
                              YoloDropped* dropped = nullptr);
  std::vector<YoloBox> Detect(const cv::Mat& bgr, const ScoreThresholds& thresholds, float nms_iou = 0.5f,
                              YoloDropped* dropped = nullptr);

 private:
  std::shared_ptr<const YoloModelInfo> info_;
  cv::dnn::Net net_;
};

}  // namespace seamap
