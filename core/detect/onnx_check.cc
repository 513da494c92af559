#include "core/detect/onnx_check.h"

#include <unordered_set>
#include <vector>

#include "core/detect/protobuf_wire.h"
#include "core/util/error.h"

namespace seamap {
namespace {

// A name from the file, at most ~60 characters of it.
std::string Short(const std::string& name) {
  if (name.size() <= 60) return name;
  return name.substr(0, 60) + "... (" + std::to_string(name.size()) + " bytes)";
}
std::string Quoted(const std::string& name) {
  return "'" + Short(name) + "'";
}

// TensorProto.DataType 1..20: bytes per element in raw_data (0: strings;
// float, uint8, int8, uint16, int16, int32, int64, string, bool, float16,
// double, uint32, uint64, complex64, complex128, bfloat16, four float8s).
constexpr int kElementBytes[21] = {-1, 4, 1, 1, 2, 2, 4, 8, 0, 1, 2, 8, 4, 8, 8, 16, 2, 1, 1, 1, 1};

// The TensorProto field that holds a type's values when there is no raw_data
// (float_data 4, int32_data 5, string_data 6, int64_data 7, double_data 10,
// uint64_data 11), and how many values each element takes (complex: 2).
constexpr int kTypedField[21] = {0, 4, 5, 5, 5, 5, 5, 7, 6, 5, 5, 10, 11, 11, 4, 10, 5, 5, 5, 5, 5};

std::string DimsText(const std::vector<int64_t>& dims) {
  std::string out = "[";
  for (size_t i = 0; i < dims.size() && i < 8; ++i) out += (i ? ", " : "") + std::to_string(dims[i]);
  return out + (dims.size() > 8 ? ", ...]" : "]");
}

class GraphCheck {
 public:
  GraphCheck(const std::string& s, const std::string& path) : s_(s), path_(path) {}

  void Model() {
    WireReader r(s_, 0, s_.size());
    int f, t;
    WireSpan graph;
    bool has_graph = false;
    while (!r.Done()) {
      if (!r.Next(&f, &t)) throw Bad("", "not a protobuf ModelProto");
      if (f == 7 && t == kWireBytes) {
        if (!r.Bytes(&graph)) throw Bad("graph", "truncated");
        has_graph = true;
      } else if (f == 25 && t == kWireBytes) {
        throw Bad("functions", "model-local functions are not supported");
      } else if (!r.Skip(t)) {
        throw Bad("", "not a protobuf ModelProto");
      }
    }
    if (!has_graph) throw Bad("graph", "the model has no graph");
    Graph(graph);
  }

 private:
  InputError Bad(const std::string& field, const std::string& why) const {
    return InputError(path_, 0, field, "not a valid ONNX model: " + why);
  }

  // A string field's payload.
  std::string Text(WireSpan span) const { return s_.substr(span.begin, span.size()); }

  void Graph(WireSpan graph) {
    std::vector<WireSpan> nodes, inputs, outputs, initialisers;
    WireReader r(s_, graph);
    int f, t;
    while (!r.Done()) {
      if (!r.Next(&f, &t)) throw Bad("graph", "malformed");
      WireSpan span;
      if (t == kWireBytes && (f == 1 || f == 5 || f == 11 || f == 12 || f == 15)) {
        if (!r.Bytes(&span)) throw Bad("graph", "malformed");
        if (f == 1) nodes.push_back(span);
        if (f == 5) initialisers.push_back(span);
        if (f == 11) inputs.push_back(span);
        if (f == 12) outputs.push_back(span);
        if (f == 15) throw Bad("graph.sparse_initializer", "sparse initializers are not supported");
      } else if (!r.Skip(t)) {
        throw Bad("graph", "malformed");
      }
    }
    for (size_t i = 0; i < initialisers.size(); ++i)
      defined_.insert(Tensor(initialisers[i], "initializer " + std::to_string(i)));
    for (size_t i = 0; i < inputs.size(); ++i) defined_.insert(ValueName(inputs[i], "input " + std::to_string(i)));
    for (size_t i = 0; i < nodes.size(); ++i) Node(nodes[i], i);
    for (size_t i = 0; i < outputs.size(); ++i) {
      const std::string name = ValueName(outputs[i], "output " + std::to_string(i));
      if (!defined_.count(name))
        throw Bad("output " + std::to_string(i), "graph output " + Quoted(name) + " is produced by no node");
    }
  }

  // ValueInfoProto: name 1, type 2 -> tensor_type 1 -> shape 2 -> dim 1 ->
  // dim_value 1; a dim OpenCV would allocate must be 0..2^24. Returns the name.
  std::string ValueName(WireSpan span, const std::string& where) const {
    std::string name;
    const auto bad = [&]() { return Bad(where, "malformed value info"); };
    // The first field `field` of a message, as a span; false when it has none.
    const auto sub = [&](WireSpan in, int field, WireSpan* out, bool* found) {
      WireReader r(s_, in);
      int f, t;
      *found = false;
      while (!r.Done()) {
        if (!r.Next(&f, &t)) throw bad();
        if (f == field && t == kWireBytes && !*found) {
          if (!r.Bytes(out)) throw bad();
          *found = true;
        } else if (!r.Skip(t)) {
          throw bad();
        }
      }
    };
    WireReader r(s_, span);
    int f, t;
    WireSpan type;
    bool has_type = false;
    while (!r.Done()) {
      if (!r.Next(&f, &t)) throw bad();
      WireSpan b;
      if ((f == 1 || f == 2) && t == kWireBytes) {
        if (!r.Bytes(&b)) throw bad();
        if (f == 1) name = Text(b);
        if (f == 2) type = b, has_type = true;
      } else if (!r.Skip(t)) {
        throw bad();
      }
    }
    WireSpan tensor, shape;
    bool found = false;
    if (has_type) sub(type, 1, &tensor, &found);
    if (found) sub(tensor, 2, &shape, &found);
    if (!found) return name;
    WireReader dims(s_, shape);
    while (!dims.Done()) {
      if (!dims.Next(&f, &t)) throw bad();
      WireSpan dim;
      if (f != 1 || t != kWireBytes) {
        if (!dims.Skip(t)) throw bad();
        continue;
      }
      if (!dims.Bytes(&dim)) throw bad();
      WireReader d(s_, dim);
      while (!d.Done()) {
        if (!d.Next(&f, &t)) throw bad();
        uint64_t v;
        if (f == 1 && t == kWireVarint) {
          if (!d.Varint(&v)) throw bad();
          if (v > (uint64_t{1} << 24))
            throw Bad(where, Quoted(name) + " has a dimension of " + std::to_string(static_cast<int64_t>(v)) +
                                 " (expected 0..16777216)");
        } else if (!d.Skip(t)) {
          throw bad();
        }
      }
    }
    return name;
  }

  // NodeProto: input 1, output 2, name 3, op_type 4, attribute 5.
  void Node(WireSpan span, size_t index) {
    std::vector<std::string> in, out;
    std::vector<WireSpan> attributes;
    std::string name, op;
    WireReader r(s_, span);
    int f, t;
    const std::string where = "node " + std::to_string(index);
    while (!r.Done()) {
      if (!r.Next(&f, &t)) throw Bad(where, "malformed node");
      WireSpan b;
      if (t == kWireBytes && f >= 1 && f <= 5) {
        if (!r.Bytes(&b)) throw Bad(where, "malformed node");
        if (f == 1) in.push_back(Text(b));
        if (f == 2) out.push_back(Text(b));
        if (f == 3) name = Text(b);
        if (f == 4) op = Text(b);
        if (f == 5) attributes.push_back(b);
      } else if (!r.Skip(t)) {
        throw Bad(where, "malformed node");
      }
    }
    const std::string field = where + " (" + (name.empty() ? "" : Short(name) + ", ") + Short(op) + ")";
    for (const WireSpan& a : attributes) Attribute(a, field);
    for (const std::string& i : in)  // "": an optional input left out
      if (!i.empty() && !defined_.count(i))
        throw Bad(field, "input " + Quoted(i) + " is not a graph input, an initializer nor an earlier node's output");
    for (const std::string& o : out) defined_.insert(o);
  }

  // AttributeProto: t 5, g 6, tensors 10, graphs 11, sparse_tensor 22, sparse_tensors 23.
  void Attribute(WireSpan span, const std::string& node) {
    WireReader r(s_, span);
    int f, t;
    while (!r.Done()) {
      if (!r.Next(&f, &t)) throw Bad(node, "malformed attribute");
      WireSpan b;
      if (t == kWireBytes && (f == 5 || f == 10)) {
        if (!r.Bytes(&b)) throw Bad(node, "malformed attribute");
        Tensor(b, node + " attribute tensor");
      } else if (t == kWireBytes && (f == 6 || f == 11)) {
        throw Bad(node, "subgraphs (If, Loop, Scan) are not supported");
      } else if (t == kWireBytes && (f == 22 || f == 23)) {
        throw Bad(node, "sparse tensors are not supported");
      } else if (!r.Skip(t)) {
        throw Bad(node, "malformed attribute");
      }
    }
  }

  // TensorProto: dims 1, data_type 2, segment 3, typed data 4-7/10/11, name 8,
  // raw_data 9, external_data 13, data_location 14. Returns its name.
  std::string Tensor(WireSpan span, const std::string& where) const {
    std::vector<int64_t> dims;
    int64_t type = 0;
    std::string name;
    bool has_raw = false, external = false;
    size_t raw_bytes = 0;
    uint64_t values[12] = {};  // per typed field number
    WireReader r(s_, span);
    int f, t;
    const auto bad = [&](const std::string& why) {
      return Bad(where + (name.empty() ? "" : " (" + Short(name) + ")"), why);
    };
    while (!r.Done()) {
      if (!r.Next(&f, &t)) throw bad("malformed tensor");
      WireSpan b;
      uint64_t v;
      if (f == 1 && t == kWireVarint) {
        if (!r.Varint(&v)) throw bad("malformed dims");
        dims.push_back(static_cast<int64_t>(v));
      } else if (f == 1 && t == kWireBytes) {
        if (!r.Bytes(&b)) throw bad("malformed dims");
        WireReader d(s_, b);
        while (!d.Done()) {
          if (!d.Varint(&v)) throw bad("malformed dims");
          dims.push_back(static_cast<int64_t>(v));
        }
      } else if (f == 2 && t == kWireVarint) {
        if (!r.Varint(&v)) throw bad("malformed data_type");
        type = static_cast<int64_t>(v);
      } else if (f == 3) {
        throw bad("segmented tensors are not supported");
      } else if ((f == 4 || f == 5 || f == 6 || f == 7 || f == 10 || f == 11) && t == kWireBytes) {
        if (!r.Bytes(&b)) throw bad("malformed data");
        if (f == 6) {
          ++values[f];  // one string
        } else if (f == 4 || f == 10) {
          const size_t width = f == 4 ? 4 : 8;
          if (b.size() % width) throw bad("packed data is not a whole number of values");
          values[f] += b.size() / width;
        } else {
          values[f] += CountPackedVarints(s_, b);
        }
      } else if ((f == 4 && t == kWireFixed32) || (f == 10 && t == kWireFixed64) ||
                 ((f == 5 || f == 7 || f == 11) && t == kWireVarint)) {
        if (!r.Skip(t)) throw bad("malformed data");
        ++values[f];
      } else if (f == 8 && t == kWireBytes) {
        if (!r.Bytes(&b)) throw bad("malformed name");
        name = Text(b);
      } else if (f == 9 && t == kWireBytes) {
        if (!r.Bytes(&b)) throw bad("malformed raw_data");
        has_raw = true;
        raw_bytes = b.size();
      } else if (f == 13 && t == kWireBytes) {
        if (!r.Skip(t)) throw bad("malformed external_data");
        external = true;
      } else if (f == 14 && t == kWireVarint) {
        if (!r.Varint(&v)) throw bad("malformed data_location");
        external = external || v == 1;
      } else if (!r.Skip(t)) {
        throw bad("malformed tensor");
      }
    }
    if (external) throw bad("its data is in an external file; the model must hold its weights");
    if (type < 1 || type > 20)
      throw bad("data_type " + std::to_string(type) + " is not a tensor type (expected 1..20)");
    // Elements the dims declare; anything past 2^48 is more than any file holds.
    constexpr uint64_t kHuge = uint64_t{1} << 48;
    uint64_t elements = 1;
    for (int64_t d : dims) {
      if (d < 0) throw bad("dims " + DimsText(dims) + " hold a negative size");
      elements = d == 0 || elements == 0 ? 0 : (static_cast<uint64_t>(d) > kHuge / elements ? kHuge : elements * d);
    }
    const std::string declared = "dims " + DimsText(dims) + " declare " +
                                 (elements >= kHuge ? std::string("over 2^48") : std::to_string(elements)) +
                                 " elements";
    const int element_bytes = kElementBytes[type], typed = kTypedField[type];
    const uint64_t per_element = type == 14 || type == 15 ? 2 : 1;
    for (int field : {4, 5, 6, 7, 10, 11})
      if (values[field] && (has_raw || field != typed))
        throw bad("holds values in TensorProto field " + std::to_string(field) + " that data_type " +
                  std::to_string(type) + (has_raw ? " with raw_data" : "") + " does not use");
    if (has_raw) {
      if (element_bytes == 0) throw bad("strings cannot be in raw_data");
      if (elements >= kHuge || elements * element_bytes != raw_bytes)
        throw bad(declared + " of " + std::to_string(element_bytes) + " bytes, but raw_data holds " +
                  std::to_string(raw_bytes) + " bytes");
    } else if (elements >= kHuge || values[typed] != elements * per_element) {
      throw bad(declared + ", but the tensor holds " + std::to_string(values[typed]) + " values");
    }
    return name;
  }

  const std::string& s_;
  const std::string& path_;
  std::unordered_set<std::string> defined_;
};

}  // namespace

void CheckOnnxGraph(const std::string& bytes, const std::string& path) {
  GraphCheck(bytes, path).Model();
}

}  // namespace seamap
