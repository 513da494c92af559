#pragma once
// PLY point clouds (the format SLAM systems and photogrammetry tools export):
// ASCII or binary of either byte order; a `vertex` element with scalar
// properties x y z (any numeric type) and any others, which are kept. The
// vertex element must come first; elements after it (faces, ...) are copied
// through unchanged. Written back in the same format with x y z as double:
// a float near northing 5e6 m resolves only 0.5 m.
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace seamap {

struct PlyProperty {
  std::string name;
  std::string type;  // char uchar short ushort int uint float double (int8 ... float64 read as these)
};

struct PointCloud {
  enum class Format { kAscii, kBinaryLittleEndian, kBinaryBigEndian };
  Format format = Format::kBinaryLittleEndian;
  std::vector<std::string> comments;           // header comments, without "comment "
  std::vector<PlyProperty> vertex_properties;  // always includes x, y, z
  std::vector<double> values;                  // size() x vertex_properties.size(), row by row
  std::vector<std::string> tail_header;        // header lines of elements after the vertex element
  std::string tail_data;                       // their data, byte for byte

  size_t size() const { return vertex_properties.empty() ? 0 : values.size() / vertex_properties.size(); }
  int Index(const std::string& property) const;  // -1 when absent
  Eigen::Vector3d Point(size_t i) const;
  void SetPoint(size_t i, const Eigen::Vector3d& p);
  bool HasNormals() const { return Index("nx") >= 0 && Index("ny") >= 0 && Index("nz") >= 0; }
  Eigen::Vector3d Normal(size_t i) const;
  void SetNormal(size_t i, const Eigen::Vector3d& n);
};

// A cloud of bare x y z doubles.
PointCloud MakePointCloud(const std::vector<Eigen::Vector3d>& points, PointCloud::Format format);

// Throws InputError(path, line, field, ...): a header line (or an ASCII data
// line) that cannot be read, no vertex element or no x y z, a list property in
// the vertex element, data shorter than the header says.
PointCloud ReadPly(const std::string& path);

// x y z written as double, other properties with their types.
void WritePly(const std::string& path, const PointCloud& cloud);

}  // namespace seamap
