#pragma once
// Hand-built ONNX models for tests (issue 33): the protobuf wire format
// written field by field, so a test makes a valid model, then damages it
// exactly where it wants, with no ONNX library and no binary fixture.
// PlantedYoloModel is tests/fixtures/make_yolo_fixtures.py's model: a
// global average pool, a 1x1 convolution with zero weights whose bias holds
// the planted output, and a reshape to the YOLO layout.
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace seamap::testing {

inline void PutVarint(std::string* out, uint64_t v) {
  while (v >= 0x80) {
    out->push_back(static_cast<char>((v & 0x7f) | 0x80));
    v >>= 7;
  }
  out->push_back(static_cast<char>(v));
}
inline void PutVarintField(std::string* out, int field, uint64_t v) {
  PutVarint(out, static_cast<uint64_t>(field) << 3);
  PutVarint(out, v);
}
inline void PutBytesField(std::string* out, int field, const std::string& bytes) {
  PutVarint(out, (static_cast<uint64_t>(field) << 3) | 2);
  PutVarint(out, bytes.size());
  out->append(bytes);
}

// TensorProto: dims 1, data_type 2, name 8, raw_data 9 (data_type 1 = float, 7 = int64).
inline std::string TensorBytes(const std::string& name, const std::vector<int64_t>& dims, int data_type,
                               const std::string& raw) {
  std::string t;
  for (int64_t d : dims) PutVarintField(&t, 1, static_cast<uint64_t>(d));
  PutVarintField(&t, 2, static_cast<uint64_t>(data_type));
  PutBytesField(&t, 8, name);
  PutBytesField(&t, 9, raw);
  return t;
}
template <typename T>
std::string RawOf(const std::vector<T>& values) {
  std::string raw(values.size() * sizeof(T), '\0');
  if (!values.empty()) std::memcpy(raw.data(), values.data(), raw.size());
  return raw;
}
inline std::string FloatTensor(const std::string& name, const std::vector<int64_t>& dims,
                               const std::vector<float>& values) {
  return TensorBytes(name, dims, 1, RawOf(values));
}

// ValueInfoProto of a float tensor: name 1, type 2 -> tensor_type 1 -> elem_type 1, shape 2 -> dim 1 -> dim_value 1.
inline std::string FloatValueInfo(const std::string& name, const std::vector<int64_t>& dims) {
  std::string shape;
  for (int64_t d : dims) {
    std::string dim;
    PutVarintField(&dim, 1, static_cast<uint64_t>(d));
    PutBytesField(&shape, 1, dim);
  }
  std::string tensor;
  PutVarintField(&tensor, 1, 1);
  PutBytesField(&tensor, 2, shape);
  std::string type;
  PutBytesField(&type, 1, tensor);
  std::string v;
  PutBytesField(&v, 1, name);
  PutBytesField(&v, 2, type);
  return v;
}

// AttributeProto INTS: name 1, ints 8, type 20 (7).
inline std::string IntsAttribute(const std::string& name, const std::vector<int64_t>& ints) {
  std::string a;
  PutBytesField(&a, 1, name);
  for (int64_t i : ints) PutVarintField(&a, 8, static_cast<uint64_t>(i));
  PutVarintField(&a, 20, 7);
  return a;
}

struct OnnxNodeSpec {
  std::string op;
  std::vector<std::string> inputs, outputs;
  std::vector<std::string> attributes;  // AttributeProto bytes
};

struct OnnxModelSpec {
  std::vector<OnnxNodeSpec> nodes;
  std::vector<std::string> initializers;     // TensorProto bytes
  std::vector<std::string> inputs, outputs;  // ValueInfoProto bytes
  std::map<std::string, std::string> metadata;
  int64_t ir_version = 7, opset = 12;
};

// ModelProto: ir_version 1, graph 7, opset_import 8, metadata_props 14;
// GraphProto: node 1, name 2, initializer 5, input 11, output 12;
// NodeProto: input 1, output 2, name 3, op_type 4, attribute 5.
inline std::string OnnxModelBytes(const OnnxModelSpec& spec) {
  std::string graph;
  for (size_t i = 0; i < spec.nodes.size(); ++i) {
    const OnnxNodeSpec& n = spec.nodes[i];
    std::string node;
    for (const auto& in : n.inputs) PutBytesField(&node, 1, in);
    for (const auto& out : n.outputs) PutBytesField(&node, 2, out);
    PutBytesField(&node, 3, n.op + "_" + std::to_string(i));
    PutBytesField(&node, 4, n.op);
    for (const auto& a : n.attributes) PutBytesField(&node, 5, a);
    PutBytesField(&graph, 1, node);
  }
  PutBytesField(&graph, 2, "seamap-test");
  for (const auto& t : spec.initializers) PutBytesField(&graph, 5, t);
  for (const auto& v : spec.inputs) PutBytesField(&graph, 11, v);
  for (const auto& v : spec.outputs) PutBytesField(&graph, 12, v);
  std::string model;
  PutVarintField(&model, 1, static_cast<uint64_t>(spec.ir_version));
  PutBytesField(&model, 2, "seamap-test");
  PutBytesField(&model, 7, graph);
  std::string opset;
  PutVarintField(&opset, 2, static_cast<uint64_t>(spec.opset));
  PutBytesField(&model, 8, opset);
  for (const auto& [key, value] : spec.metadata) {
    std::string kv;
    PutBytesField(&kv, 1, key);
    PutBytesField(&kv, 2, value);
    PutBytesField(&model, 14, kv);
  }
  return model;
}

// A model whose only output, of `out_shape` (e.g. {1, 4 + C, N} for YOLOv8),
// holds `values` whatever the image (input 1 x 3 x side x side).
inline OnnxModelSpec PlantedYoloModel(const std::vector<int64_t>& out_shape, const std::vector<float>& values,
                                      const std::map<std::string, std::string>& metadata, int64_t side = 64) {
  const int64_t m = static_cast<int64_t>(values.size());
  OnnxModelSpec spec;
  spec.inputs.push_back(FloatValueInfo("images", {1, 3, side, side}));
  spec.outputs.push_back(FloatValueInfo("output0", out_shape));
  spec.initializers.push_back(FloatTensor("w", {m, 3, 1, 1}, std::vector<float>(static_cast<size_t>(m) * 3, 0.0f)));
  spec.initializers.push_back(FloatTensor("b", {m}, values));
  spec.initializers.push_back(TensorBytes("shape", {static_cast<int64_t>(out_shape.size())}, 7, RawOf(out_shape)));
  spec.nodes.push_back({"GlobalAveragePool", {"images"}, {"pooled"}, {}});
  spec.nodes.push_back({"Conv", {"pooled", "w", "b"}, {"planted"}, {IntsAttribute("kernel_shape", {1, 1})}});
  spec.nodes.push_back({"Reshape", {"planted", "shape"}, {"output0"}, {}});
  spec.metadata = metadata;
  return spec;
}

// YOLOv8 values [4 + C, N] from boxes given as rows {cx, cy, w, h, p_0 .. p_C-1}.
inline std::vector<float> V8Values(const std::vector<std::vector<float>>& rows) {
  const size_t n = rows.size(), k = rows.empty() ? 0 : rows[0].size();
  std::vector<float> out(n * k);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < k; ++j) out[j * n + i] = rows[i][j];
  return out;
}

}  // namespace seamap::testing
