#include "core/georef/point_cloud_ply.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "core/util/error.h"
#include "core/util/input_file.h"

namespace seamap {
namespace {

// Canonical type name -> size in bytes; PLY's sized aliases map onto them.
const std::map<std::string, int>& TypeSizes() {
  static const std::map<std::string, int> sizes = {{"char", 1}, {"uchar", 1}, {"short", 2}, {"ushort", 2},
                                                   {"int", 4},  {"uint", 4},  {"float", 4}, {"double", 8}};
  return sizes;
}

std::string CanonicalType(const std::string& type) {
  static const std::map<std::string, std::string> aliases = {
      {"int8", "char"}, {"uint8", "uchar"}, {"int16", "short"},   {"uint16", "ushort"},
      {"int32", "int"}, {"uint32", "uint"}, {"float32", "float"}, {"float64", "double"}};
  auto it = aliases.find(type);
  if (it != aliases.end()) return it->second;
  return TypeSizes().count(type) ? type : "";
}

bool HostIsLittleEndian() {
  const uint16_t one = 1;
  uint8_t first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

template <typename T>
double Load(const char* bytes, bool swap) {
  char buffer[sizeof(T)];
  std::memcpy(buffer, bytes, sizeof(T));
  if (swap) std::reverse(buffer, buffer + sizeof(T));
  T value;
  std::memcpy(&value, buffer, sizeof(T));
  return static_cast<double>(value);
}

double LoadValue(const std::string& type, const char* bytes, bool swap) {
  if (type == "char") return Load<int8_t>(bytes, swap);
  if (type == "uchar") return Load<uint8_t>(bytes, swap);
  if (type == "short") return Load<int16_t>(bytes, swap);
  if (type == "ushort") return Load<uint16_t>(bytes, swap);
  if (type == "int") return Load<int32_t>(bytes, swap);
  if (type == "uint") return Load<uint32_t>(bytes, swap);
  if (type == "float") return Load<float>(bytes, swap);
  return Load<double>(bytes, swap);
}

template <typename T>
void Store(double value, bool swap, std::string* out) {
  const T v = static_cast<T>(value);
  char buffer[sizeof(T)];
  std::memcpy(buffer, &v, sizeof(T));
  if (swap) std::reverse(buffer, buffer + sizeof(T));
  out->append(buffer, sizeof(T));
}

void StoreValue(const std::string& type, double value, bool swap, std::string* out) {
  if (type == "char") return Store<int8_t>(std::lround(value), swap, out);
  if (type == "uchar") return Store<uint8_t>(std::lround(value), swap, out);
  if (type == "short") return Store<int16_t>(std::lround(value), swap, out);
  if (type == "ushort") return Store<uint16_t>(std::lround(value), swap, out);
  if (type == "int") return Store<int32_t>(std::llround(value), swap, out);
  if (type == "uint") return Store<uint32_t>(std::llround(value), swap, out);
  if (type == "float") return Store<float>(value, swap, out);
  Store<double>(value, swap, out);
}

bool IsCoordinate(const std::string& name) {
  return name == "x" || name == "y" || name == "z";
}

}  // namespace

int PointCloud::Index(const std::string& property) const {
  for (size_t i = 0; i < vertex_properties.size(); ++i)
    if (vertex_properties[i].name == property) return static_cast<int>(i);
  return -1;
}

Eigen::Vector3d PointCloud::Point(size_t i) const {
  const size_t n = vertex_properties.size();
  return {values[i * n + Index("x")], values[i * n + Index("y")], values[i * n + Index("z")]};
}

void PointCloud::SetPoint(size_t i, const Eigen::Vector3d& p) {
  const size_t n = vertex_properties.size();
  values[i * n + Index("x")] = p.x();
  values[i * n + Index("y")] = p.y();
  values[i * n + Index("z")] = p.z();
}

Eigen::Vector3d PointCloud::Normal(size_t i) const {
  const size_t n = vertex_properties.size();
  return {values[i * n + Index("nx")], values[i * n + Index("ny")], values[i * n + Index("nz")]};
}

void PointCloud::SetNormal(size_t i, const Eigen::Vector3d& v) {
  const size_t n = vertex_properties.size();
  values[i * n + Index("nx")] = v.x();
  values[i * n + Index("ny")] = v.y();
  values[i * n + Index("nz")] = v.z();
}

PointCloud MakePointCloud(const std::vector<Eigen::Vector3d>& points, PointCloud::Format format) {
  PointCloud cloud;
  cloud.format = format;
  cloud.vertex_properties = {{"x", "double"}, {"y", "double"}, {"z", "double"}};
  cloud.values.reserve(points.size() * 3);
  for (const auto& p : points) cloud.values.insert(cloud.values.end(), {p.x(), p.y(), p.z()});
  return cloud;
}

PointCloud ReadPly(const std::string& path) {
  RegularFileBytes(path, "point cloud");  // /dev/zero or a FIFO would never end
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the point cloud");
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());

  PointCloud cloud;
  size_t pos = 0;
  int line_number = 0;
  auto next_line = [&](std::string* line) {
    if (pos >= data.size()) return false;
    size_t end = data.find('\n', pos);
    if (end == std::string::npos) end = data.size();
    *line = data.substr(pos, end - pos);
    if (!line->empty() && line->back() == '\r') line->pop_back();
    pos = end + 1;
    ++line_number;
    return true;
  };

  std::string line;
  if (!next_line(&line) || line != "ply") throw InputError(path, 1, "", "not a PLY file (first line is not 'ply')");
  long vertex_count = -1;
  int vertex_line = 0;
  bool in_vertex = false, have_format = false, ended = false;
  while (next_line(&line)) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "end_header") {
      ended = true;
      break;
    }
    if (keyword.empty() || keyword == "obj_info") continue;
    if (keyword == "comment") {
      cloud.comments.push_back(line.size() > 8 ? line.substr(8) : "");
    } else if (keyword == "format") {
      std::string format, version;
      words >> format >> version;
      if (format == "ascii")
        cloud.format = PointCloud::Format::kAscii;
      else if (format == "binary_little_endian")
        cloud.format = PointCloud::Format::kBinaryLittleEndian;
      else if (format == "binary_big_endian")
        cloud.format = PointCloud::Format::kBinaryBigEndian;
      else
        throw InputError(path, line_number, "format", "unknown PLY format '" + format + "'");
      have_format = true;
    } else if (keyword == "element") {
      std::string name;
      long count = -1;
      words >> name >> count;
      if (count < 0) throw InputError(path, line_number, "element", "expected 'element NAME COUNT'");
      if (name == "vertex") {
        if (vertex_count >= 0 || !cloud.tail_header.empty())
          throw InputError(path, line_number, "element",
                           "the vertex element must come first (and once); found it after another element");
        vertex_count = count;
        vertex_line = line_number;
        in_vertex = true;
      } else {
        if (vertex_count < 0)
          throw InputError(path, line_number, "element",
                           "element '" + name + "' before the vertex element; the vertex element must come first");
        in_vertex = false;
        cloud.tail_header.push_back(line);
      }
    } else if (keyword == "property") {
      if (!in_vertex) {
        if (cloud.tail_header.empty()) throw InputError(path, line_number, "property", "property outside an element");
        cloud.tail_header.push_back(line);
        continue;
      }
      std::string type, name;
      words >> type >> name;
      if (type == "list")
        throw InputError(path, line_number, "property", "list property in the vertex element: not supported");
      const std::string canonical = CanonicalType(type);
      if (canonical.empty() || name.empty())
        throw InputError(path, line_number, "property", "expected 'property TYPE NAME' with a numeric type");
      cloud.vertex_properties.push_back({name, canonical});
    } else {
      throw InputError(path, line_number, keyword, "unknown header keyword '" + keyword + "'");
    }
  }
  if (!ended) throw InputError(path, line_number, "end_header", "header has no 'end_header' line");
  if (!have_format) throw InputError(path, line_number, "format", "header has no format line");
  if (vertex_count < 0) throw InputError(path, line_number, "element", "no vertex element");
  for (const char* axis : {"x", "y", "z"})
    if (cloud.Index(axis) < 0)
      throw InputError(path, line_number, axis, "the vertex element has no '" + std::string(axis) + "' property");

  pos = std::min(pos, data.size());
  const size_t n = cloud.vertex_properties.size();
  // The count is checked against the bytes that follow before anything is
  // allocated: a 117-byte header may declare 1.5e8 vertices. Binary records
  // have a fixed size; an ASCII value takes at least a digit and a separator.
  const size_t left = data.size() - pos;
  size_t record = 0;
  for (const auto& p : cloud.vertex_properties) record += TypeSizes().at(p.type);
  const bool ascii = cloud.format == PointCloud::Format::kAscii;
  const size_t least = ascii ? 2 * n : record;
  if (static_cast<unsigned long>(vertex_count) > left / least)
    throw InputError(path, vertex_line, "vertex",
                     "declares " + std::to_string(vertex_count) + " vertices, but the " + std::to_string(left) +
                         " bytes after the header hold at most " + std::to_string(left / least) + " (" +
                         (ascii ? "at least 2 bytes a value" : std::to_string(record) + " bytes a vertex") + ")");
  cloud.values.resize(static_cast<size_t>(vertex_count) * n);
  if (cloud.format == PointCloud::Format::kAscii) {
    for (long v = 0; v < vertex_count; ++v) {
      do {
        if (!next_line(&line))
          throw InputError(path, line_number, "vertex",
                           "expected " + std::to_string(vertex_count) + " vertices, found " + std::to_string(v));
      } while (line.find_first_not_of(" \t") == std::string::npos);
      const char* p = line.c_str();
      for (size_t k = 0; k < n; ++k) {
        char* end = nullptr;
        const double value = std::strtod(p, &end);
        if (end == p) throw InputError(path, line_number, cloud.vertex_properties[k].name, "expected a number");
        cloud.values[v * n + k] = value;
        p = end;
      }
    }
    cloud.tail_data = pos < data.size() ? data.substr(pos) : "";
  } else {
    const bool swap = (cloud.format == PointCloud::Format::kBinaryLittleEndian) != HostIsLittleEndian();
    if (data.size() - pos < record * vertex_count)
      throw InputError(path, 0, "vertex",
                       "file ends inside the vertex data: " + std::to_string(vertex_count) + " vertices of " +
                           std::to_string(record) + " bytes need " + std::to_string(record * vertex_count) +
                           ", found " + std::to_string(data.size() - pos));
    for (long v = 0; v < vertex_count; ++v)
      for (size_t k = 0; k < n; ++k) {
        cloud.values[v * n + k] = LoadValue(cloud.vertex_properties[k].type, data.data() + pos, swap);
        pos += TypeSizes().at(cloud.vertex_properties[k].type);
      }
    cloud.tail_data = data.substr(pos);
  }
  return cloud;
}

void WritePly(const std::string& path, const PointCloud& cloud) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw InputError(path, 0, "", "cannot write the point cloud");
  const char* format = cloud.format == PointCloud::Format::kAscii                ? "ascii"
                       : cloud.format == PointCloud::Format::kBinaryLittleEndian ? "binary_little_endian"
                                                                                 : "binary_big_endian";
  std::string text = "ply\nformat " + std::string(format) + " 1.0\n";
  for (const auto& c : cloud.comments) text += "comment " + c + "\n";
  text += "element vertex " + std::to_string(cloud.size()) + "\n";
  std::vector<std::string> types;
  for (const auto& p : cloud.vertex_properties) {
    types.push_back(IsCoordinate(p.name) ? "double" : p.type);
    text += "property " + types.back() + " " + p.name + "\n";
  }
  for (const auto& l : cloud.tail_header) text += l + "\n";
  text += "end_header\n";
  const size_t n = cloud.vertex_properties.size();
  if (cloud.format == PointCloud::Format::kAscii) {
    char buffer[64];
    for (size_t v = 0; v < cloud.size(); ++v) {
      for (size_t k = 0; k < n; ++k) {
        const double value = cloud.values[v * n + k];
        if (types[k] == "double" || types[k] == "float")
          std::snprintf(buffer, sizeof buffer, "%s%.*g", k ? " " : "", types[k] == "double" ? 17 : 9, value);
        else
          std::snprintf(buffer, sizeof buffer, "%s%lld", k ? " " : "", std::llround(value));
        text += buffer;
      }
      text += "\n";
    }
  } else {
    const bool swap = (cloud.format == PointCloud::Format::kBinaryLittleEndian) != HostIsLittleEndian();
    text.reserve(text.size() + cloud.size() * n * 8);
    for (size_t v = 0; v < cloud.size(); ++v)
      for (size_t k = 0; k < n; ++k) StoreValue(types[k], cloud.values[v * n + k], swap, &text);
  }
  text += cloud.tail_data;
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) throw InputError(path, 0, "", "cannot write the point cloud");
}

}  // namespace seamap
