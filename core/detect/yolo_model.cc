#include "core/detect/yolo_model.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/detect/onnx_meta.h"
#include "core/util/error.h"

namespace seamap {
namespace {

cv::dnn::Net LoadNet(const std::string& path) {
  try {
    cv::dnn::Net net = cv::dnn::readNetFromONNX(path);
    net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
    net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
    return net;
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "", std::string("OpenCV cannot import this ONNX model: ") + e.what());
  } catch (const std::exception& e) {  // e.g. std::length_error from shapes OpenCV does not check
    throw InputError(path, 0, "", std::string("OpenCV cannot import this ONNX model: ") + e.what());
  }
}

cv::Mat Forward(cv::dnn::Net& net, const cv::Mat& letterboxed) {
  net.setInput(cv::dnn::blobFromImage(letterboxed, 1 / 255.0, cv::Size(), cv::Scalar(), /*swapRB=*/true,
                                      /*crop=*/false));
  return net.forward();
}

std::string ContentName(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  uint64_t h = 1469598103934665603ull;  // FNV-1a 64
  char buf[65536];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) h = (h ^ static_cast<uint8_t>(buf[i])) * 1099511628211ull;
    if (!in) break;
  }
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return std::filesystem::path(path).filename().string() + "#" + hex;
}

}  // namespace

std::shared_ptr<const YoloModelInfo> YoloModel::Inspect(const std::string& path, const std::string& classes_path) {
  const OnnxInfo onnx = ReadOnnxInfo(path);  // a missing, irregular, huge or malformed file: refused here
  auto info = std::make_shared<YoloModelInfo>();
  info->path = path;
  info->name = ContentName(path);
  if (!classes_path.empty()) {
    info->class_names = ReadClassesFile(classes_path);
    info->names_source = "--classes " + classes_path;
  } else if (onnx.metadata.count("names")) {
    info->class_names = ParseClassNames(onnx.metadata.at("names"), path);
    info->names_source = path + " metadata 'names'";
  } else {
    throw InputError(path, 0, "names", "no class names: give --classes FILE or put 'names' in the model's metadata");
  }
  const int c = static_cast<int>(info->class_names.size());
  info->class_sizes_m.assign(c, 0.0);
  if (onnx.metadata.count("seamap.class_sizes_m"))
    info->class_sizes_m = ParseClassSizes(onnx.metadata.at("seamap.class_sizes_m"), info->class_names, path);
  if (onnx.metadata.count("seamap.layer")) info->layer = Excerpt(onnx.metadata.at("seamap.layer"));
  if (onnx.metadata.count("seamap.min_score")) {
    const std::string& text = onnx.metadata.at("seamap.min_score");
    char* end = nullptr;
    const double s = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !(s >= kMinScoreFloor && s <= 1))
      throw InputError(path, 0, "seamap.min_score",
                       "expected a score between 0.001 and 1 in the metadata, got '" + Excerpt(text) + "'");
    info->min_score = static_cast<float>(s);
  }
  if (onnx.metadata.count("seamap.class_min_scores"))
    info->class_min_scores =
        ParseClassMinScores(onnx.metadata.at("seamap.class_min_scores"), info->class_names, info->min_score, path);
  // Input size: graph input dims, else metadata imgsz, else 640.
  const auto& d = onnx.input_dims;
  if (d.size() == 4 && d[2] > 0 && d[3] > 0) {
    info->input = cv::Size(static_cast<int>(d[3]), static_cast<int>(d[2]));
  } else if (onnx.metadata.count("imgsz")) {
    try {
      const auto j = nlohmann::json::parse(onnx.metadata.at("imgsz"));
      const auto side = [&](const nlohmann::json& v) {  // an integer that fits; the range is checked below
        if (!v.is_number_integer() || v.get<int64_t>() < 0 || v.get<int64_t>() > 1 << 20)
          throw InputError(path, 0, "imgsz", "expected an integer or [height, width]");
        return static_cast<int>(v.get<int64_t>());
      };
      info->input = j.is_array() ? cv::Size(side(j.at(1)), side(j.at(0))) : cv::Size(side(j), side(j));
    } catch (const nlohmann::json::exception&) {
      throw InputError(path, 0, "imgsz", "expected an integer or [height, width]");
    }
  }
  if (info->input.width < 32 || info->input.height < 32 || info->input.width > 4096 || info->input.height > 4096)
    throw InputError(path, 0, "input",
                     "input size " + std::to_string(info->input.width) + "x" + std::to_string(info->input.height) +
                         " is outside 32..4096 px");
  if (onnx.outputs != 1)
    throw InputError(path, 0, "output",
                     "the model has " + std::to_string(onnx.outputs) +
                         " outputs; a YOLO export has one ([1, N, 5+C] or [1, 4+C, N])");
  // Dry run on a grey input: the output shape, and models OpenCV cannot run.
  cv::dnn::Net net = LoadNet(path);
  cv::Mat out;
  try {
    out = Forward(net, cv::Mat(info->input, CV_8UC3, cv::Scalar::all(114)));
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "",
                     std::string("OpenCV 4.6 cannot run this model (re-export with the box decoding in 4-D "
                                 "tensors, or use OpenCV >= 4.7): ") +
                         e.what());
  } catch (const std::exception& e) {
    throw InputError(path, 0, "", std::string("OpenCV cannot run this model: ") + e.what());
  }
  for (int i = 0; i < out.dims; ++i) info->output_shape.push_back(out.size[i]);
  info->layout = RecogniseYoloLayout(info->output_shape, c, path, info->names_source);
  return info;
}

YoloModel::YoloModel(std::shared_ptr<const YoloModelInfo> info) : info_(std::move(info)), net_(LoadNet(info_->path)) {}

std::vector<YoloBox> YoloModel::Detect(const cv::Mat& bgr, float min_score, float nms_iou, YoloDropped* dropped) {
  ScoreThresholds thresholds;
  thresholds.all = min_score;
  return Detect(bgr, thresholds, nms_iou, dropped);
}

std::vector<YoloBox> YoloModel::Detect(const cv::Mat& bgr, const ScoreThresholds& thresholds, float nms_iou,
                                       YoloDropped* dropped) {
  const Letterbox lb = MakeLetterbox(bgr.size(), info_->input);
  cv::Mat out = Forward(net_, ApplyLetterbox(bgr, lb));
  if (!out.isContinuous()) out = out.clone();
  std::vector<YoloBox> boxes = KeepBestBoxes(
      NmsPerClass(DecodeYolo(out, info_->layout, static_cast<int>(info_->class_names.size()), thresholds, dropped),
                  nms_iou),
      kMaxYoloBoxes, dropped);
  for (YoloBox& b : boxes) b = UndoLetterbox(b, lb);
  return boxes;
}

}  // namespace seamap
