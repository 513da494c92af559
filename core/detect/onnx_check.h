#pragma once
// What must hold in an ONNX model before OpenCV reads it (issue 33): OpenCV
// 4.6 trusts the file and crashes on a tensor whose data is shorter than its
// dims say, or on a node whose input nothing defines. Checked on the wire
// format (core/detect/protobuf_wire.h), so a hostile model costs its own
// size in memory and never reaches cv::dnn.
#include <cstdint>
#include <string>

namespace seamap {

// Largest model file read: a YOLO export for this tool is a few MB.
constexpr int64_t kMaxOnnxModelBytes = 256ll << 20;

// Throws InputError(path, 0, field, ...) naming the tensor or node and what
// was expected when: a tensor's data (raw_data or the typed list) does not
// hold exactly the elements its dims declare, a dim is negative, the data
// type is unknown, the data is external or sparse; a node's input is neither
// a graph input, an initializer nor an earlier node's output; a graph output
// is produced by nothing; a node holds a subgraph (If, Loop, Scan).
// `bytes` is a ModelProto that ParseOnnxInfo has read.
void CheckOnnxGraph(const std::string& bytes, const std::string& path);

}  // namespace seamap
