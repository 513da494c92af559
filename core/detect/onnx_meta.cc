#include "core/detect/onnx_meta.h"

#include <cctype>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/detect/onnx_check.h"
#include "core/detect/protobuf_wire.h"
#include "core/util/error.h"
#include "core/util/input_file.h"

namespace seamap {
namespace {

using Span = WireSpan;

bool ReadKeyValue(const std::string& s, Span span, std::string* key, std::string* value) {
  WireReader r(s, span.begin, span.end);
  int f, t;
  while (!r.Done()) {
    if (!r.Next(&f, &t)) return false;
    size_t b, e;
    if ((f == 1 || f == 2) && t == 2) {
      if (!r.Bytes(&b, &e)) return false;
      (f == 1 ? *key : *value) = s.substr(b, e - b);
    } else if (!r.Skip(t)) {
      return false;
    }
  }
  return true;
}

// The sub-message `field` (first occurrence) of a message, if any.
bool Sub(const std::string& s, Span span, int field, Span* out) {
  WireReader r(s, span.begin, span.end);
  int f, t;
  while (!r.Done()) {
    if (!r.Next(&f, &t)) return false;
    if (f == field && t == 2) return r.Bytes(&out->begin, &out->end);
    if (!r.Skip(t)) return false;
  }
  return false;
}

// ValueInfoProto -> name and dims (type 2 -> tensor_type 1 -> shape 2 -> dim 1 -> value 1 | param 2).
bool ReadValueInfo(const std::string& s, Span span, std::string* name, std::vector<int64_t>* dims) {
  WireReader r(s, span.begin, span.end);
  int f, t;
  Span type{}, tensor{}, shape{};
  bool has_type = false;
  while (!r.Done()) {
    if (!r.Next(&f, &t)) return false;
    size_t b, e;
    if (t == 2 && (f == 1 || f == 2)) {
      if (!r.Bytes(&b, &e)) return false;
      if (f == 1)
        *name = s.substr(b, e - b);
      else
        type = {b, e}, has_type = true;
    } else if (!r.Skip(t)) {
      return false;
    }
  }
  dims->clear();
  if (!has_type || !Sub(s, type, 1, &tensor) || !Sub(s, tensor, 2, &shape)) return true;
  WireReader sr(s, shape.begin, shape.end);
  while (!sr.Done()) {
    if (!sr.Next(&f, &t)) return false;
    size_t b, e;
    if (f == 1 && t == 2) {
      if (!sr.Bytes(&b, &e)) return false;
      WireReader dr(s, b, e);
      int64_t value = -1;
      while (!dr.Done()) {
        int df, dt;
        if (!dr.Next(&df, &dt)) return false;
        uint64_t v;
        if (df == 1 && dt == 0) {
          if (!dr.Varint(&v)) return false;
          value = static_cast<int64_t>(v);
        } else if (!dr.Skip(dt)) {
          return false;
        }
      }
      dims->push_back(value);
    } else if (!sr.Skip(t)) {
      return false;
    }
  }
  return true;
}

std::string Trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

// A whole file of at most `max_bytes`; a FIFO, a device (/dev/zero) or a
// larger file is refused before it is read.
std::string ReadBoundedFile(const std::string& path, int64_t max_bytes, const std::string& field,
                            const std::string& what) {
  const int64_t size = RegularFileBytes(path, what, field, max_bytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, field, "cannot read the " + what);
  std::string bytes(static_cast<size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (static_cast<size_t>(in.gcount()) != bytes.size()) throw InputError(path, 0, field, "cannot read the " + what);
  return bytes;
}

}  // namespace

std::string Excerpt(const std::string& text) {
  if (text.size() <= 100) return text;
  return text.substr(0, 100) + "... (" + std::to_string(text.size()) + " bytes)";
}

OnnxInfo ParseOnnxInfo(const std::string& s, const std::string& path) {
  const auto bad = [&](const std::string& why) { return InputError(path, 0, "", "not an ONNX model (" + why + ")"); };
  OnnxInfo info;
  WireReader r(s, 0, s.size());
  int f, t;
  bool has_ir = false;
  Span graph{};
  bool has_graph = false;
  while (!r.Done()) {
    if (!r.Next(&f, &t)) throw bad("not a protobuf ModelProto");
    size_t b, e;
    if (f == 1 && t == 0) {
      uint64_t v;
      if (!r.Varint(&v)) throw bad("truncated ir_version");
      info.ir_version = static_cast<int64_t>(v);
      has_ir = true;
    } else if (f == 7 && t == 2) {
      if (!r.Bytes(&b, &e)) throw bad("truncated graph");
      graph = {b, e};
      has_graph = true;
    } else if (f == 14 && t == 2) {
      if (!r.Bytes(&b, &e)) throw bad("truncated metadata_props");
      std::string key, value;
      if (!ReadKeyValue(s, {b, e}, &key, &value)) throw bad("malformed metadata_props");
      info.metadata[key] = value;
    } else if (!r.Skip(t)) {
      throw bad("not a protobuf ModelProto");
    }
  }
  if (!has_ir || !has_graph) throw bad(has_ir ? "no graph" : "no ir_version");
  // GraphProto: initializer 5 (TensorProto, name 8), input 11, output 12.
  std::set<std::string> initialisers;
  std::vector<Span> inputs;
  WireReader g(s, graph.begin, graph.end);
  while (!g.Done()) {
    if (!g.Next(&f, &t)) throw bad("malformed graph");
    size_t b, e;
    if (t == 2 && (f == 5 || f == 11 || f == 12)) {
      if (!g.Bytes(&b, &e)) throw bad("malformed graph");
      if (f == 11) inputs.push_back({b, e});
      if (f == 12) ++info.outputs;
      if (f == 5) {
        WireReader tr(s, b, e);
        int tf, tt;
        while (!tr.Done()) {
          if (!tr.Next(&tf, &tt)) throw bad("malformed initializer");
          size_t nb, ne;
          if (tf == 8 && tt == 2) {
            if (!tr.Bytes(&nb, &ne)) throw bad("malformed initializer");
            initialisers.insert(s.substr(nb, ne - nb));
          } else if (!tr.Skip(tt)) {
            throw bad("malformed initializer");
          }
        }
      }
    } else if (!g.Skip(t)) {
      throw bad("malformed graph");
    }
  }
  for (const Span& in : inputs) {
    std::string name;
    std::vector<int64_t> dims;
    if (!ReadValueInfo(s, in, &name, &dims)) throw bad("malformed graph input");
    if (initialisers.count(name)) continue;
    info.input_dims = dims;
    break;
  }
  // OpenCV trusts the rest (tensor sizes, node inputs): checked here, before it reads the file.
  CheckOnnxGraph(s, path);
  return info;
}

OnnxInfo ReadOnnxInfo(const std::string& path) {
  return ParseOnnxInfo(ReadBoundedFile(path, kMaxOnnxModelBytes, "", "model file"), path);
}

std::vector<std::string> ParseClassNames(const std::string& text, const std::string& source) {
  const std::string t = Trim(text);
  const auto bad = [&]() {
    return InputError(
        source, 0, "names",
        "expected a JSON list of class names or a Python dict {0: 'name', ...}, got '" + Excerpt(t) + "'");
  };
  if (t.empty()) throw bad();
  if (t.front() == '[') {
    try {
      std::vector<std::string> names;
      for (const auto& v : nlohmann::json::parse(t)) names.push_back(v.get<std::string>());
      if (names.empty()) throw bad();
      for (size_t k = 0; k < names.size(); ++k)
        if (Trim(names[k]).empty())
          throw InputError(source, 0, "names",
                           "class " + std::to_string(k) + " has an empty name (expected a name per class)");
      return names;
    } catch (const nlohmann::json::exception&) {
      throw bad();
    }
  }
  if (t.front() != '{' || t.back() != '}') throw bad();
  // {0: 'tyre', 1: "crate"}: integer keys, quoted values (no escapes in class names).
  std::map<int, std::string> by_id;
  size_t i = 1;
  const auto skip_space = [&]() {
    while (i < t.size() && std::isspace(static_cast<unsigned char>(t[i]))) ++i;
  };
  while (true) {
    skip_space();
    if (i < t.size() && t[i] == '}') break;
    size_t start = i;
    while (i < t.size() && std::isdigit(static_cast<unsigned char>(t[i]))) ++i;
    if (i == start) throw bad();
    // Ids are 0..C-1: more than 6 digits is no id a model has (and would overflow an int).
    if (i - start > 6)
      throw InputError(source, 0, "names",
                       "class id '" + Excerpt(t.substr(start, i - start)) + "' is too large (expected 0..C-1)");
    const int id = std::stoi(t.substr(start, i - start));
    skip_space();
    if (i >= t.size() || t[i] != ':') throw bad();
    ++i;
    skip_space();
    if (i >= t.size() || (t[i] != '\'' && t[i] != '"')) throw bad();
    const char q = t[i++];
    const size_t close = t.find(q, i);
    if (close == std::string::npos) throw bad();
    by_id[id] = t.substr(i, close - i);
    i = close + 1;
    skip_space();
    if (i < t.size() && t[i] == ',') ++i;
  }
  std::vector<std::string> names;
  for (const auto& [id, name] : by_id) {
    if (id != static_cast<int>(names.size())) throw bad();  // ids 0..C-1, no gaps
    names.push_back(name);
  }
  if (names.empty()) throw bad();
  for (size_t k = 0; k < names.size(); ++k)
    if (Trim(names[k]).empty())
      throw InputError(source, 0, "names",
                       "class " + std::to_string(k) + " has an empty name (expected a name per class)");
  return names;
}

std::vector<std::string> ReadClassesFile(const std::string& path) {
  std::istringstream in(ReadBoundedFile(path, kMaxClassesFileBytes, "--classes", "classes file"));
  std::vector<std::string> names;
  std::string line;
  while (std::getline(in, line)) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    line = Trim(line);
    if (!line.empty()) names.push_back(line);
  }
  if (names.empty()) throw InputError(path, 0, "--classes", "no class names (expected one per line)");
  return names;
}

std::vector<double> ParseClassSizes(const std::string& text, const std::vector<std::string>& names,
                                    const std::string& source) {
  std::vector<double> sizes(names.size(), 0.0);
  const auto bad = [&]() {
    return InputError(source, 0, "seamap.class_sizes_m",
                      "expected {\"class\": metres or [min, max], ...} or a list of them in class order");
  };
  try {
    // A class's size: metres, or its [smallest, largest] range (the largest decides the levels).
    const auto size = [&](const nlohmann::json& v) {
      if (v.is_array() && v.size() == 2) return std::max(v[0].get<double>(), v[1].get<double>());
      if (v.is_number()) return v.get<double>();
      throw bad();
    };
    const auto j = nlohmann::json::parse(text);
    if (j.is_array()) {
      for (size_t i = 0; i < j.size() && i < sizes.size(); ++i) sizes[i] = size(j[i]);
    } else if (j.is_object()) {
      for (size_t i = 0; i < names.size(); ++i)
        if (j.contains(names[i])) sizes[i] = size(j[names[i]]);
    } else {
      throw bad();
    }
  } catch (const nlohmann::json::exception&) {
    throw bad();
  }
  for (double s : sizes)
    if (!(s >= 0) || s > 1e4) throw bad();
  return sizes;
}

}  // namespace seamap
