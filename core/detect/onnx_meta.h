#pragma once
// What OpenCV does not tell about an ONNX model: whether the file is ONNX at
// all, the graph's input dims and the metadata (class names, sizes, layer).
// A ~100-line protobuf wire-format reader, so no protobuf schema is needed.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace seamap {

struct OnnxInfo {
  int64_t ir_version = 0;
  std::vector<int64_t> input_dims;              // first graph input that is not an initializer; -1 = symbolic
  int outputs = 0;                              // graph outputs
  std::map<std::string, std::string> metadata;  // metadata_props
};

// Throws InputError(path, 0, "", "not an ONNX model ...") unless the file
// parses as a ModelProto with ir_version (field 1) and graph (field 7) that
// CheckOnnxGraph passes; a file that is not regular or over
// kMaxOnnxModelBytes is refused before it is read.
OnnxInfo ReadOnnxInfo(const std::string& path);
OnnxInfo ParseOnnxInfo(const std::string& bytes, const std::string& path);

// Class names from metadata `names`: a JSON list (["tyre", "crate"]) or the
// Python dict literal Ultralytics writes ({0: 'tyre', 1: 'crate'}). Throws
// InputError(source, 0, "names", ...) when it is neither, or a name is empty.
std::vector<std::string> ParseClassNames(const std::string& text, const std::string& source);

// At most ~100 characters of a text from a model or file, for a message.
std::string Excerpt(const std::string& text);

// Largest classes file read (one name per line: a few hundred bytes).
constexpr int64_t kMaxClassesFileBytes = 1 << 20;

// A classes file: one name per line, blank lines and '#' comments skipped.
// Throws InputError naming the file when it is missing, not a regular file,
// over kMaxClassesFileBytes or has no names.
std::vector<std::string> ReadClassesFile(const std::string& path);

// `seamap.class_sizes_m`: a JSON object {"tyre": 1.0, ...} or a list in
// class order. Returns sizes per class (0 where unknown). Throws InputError
// naming the key when malformed.
std::vector<double> ParseClassSizes(const std::string& text, const std::vector<std::string>& names,
                                    const std::string& source);

}  // namespace seamap
