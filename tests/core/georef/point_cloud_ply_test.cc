#include "core/georef/point_cloud_ply.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;
using ::seamap::testing::WriteFile;

std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(PointCloudPly, AsciiWithOtherPropertiesAndFaces) {
  TempDir dir;
  const std::string path = WriteFile(dir / "a.ply",
                                     "ply\nformat ascii 1.0\ncomment from a SLAM\n"
                                     "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                                     "property uchar red\nelement face 1\nproperty list uchar int vertex_indices\n"
                                     "end_header\n1.5 2 3 255\n-1 0.25 7 12\n3 0 1 1\n")
                               .string();
  PointCloud cloud = ReadPly(path);
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_EQ(cloud.format, PointCloud::Format::kAscii);
  EXPECT_EQ(cloud.Point(1), Eigen::Vector3d(-1, 0.25, 7));
  EXPECT_EQ(cloud.values[cloud.Index("red")], 255);
  EXPECT_EQ(cloud.comments, std::vector<std::string>{"from a SLAM"});
  cloud.SetPoint(0, {500000.123456, 5650000.654321, -12.5});
  const std::string out = (dir / "b.ply").string();
  WritePly(out, cloud);
  const std::string text = ReadAll(out);
  EXPECT_NE(text.find("property double x"), std::string::npos);  // UTM needs doubles
  EXPECT_NE(text.find("property uchar red"), std::string::npos);
  EXPECT_NE(text.find("element face 1"), std::string::npos);
  EXPECT_NE(text.find("3 0 1 1\n"), std::string::npos);  // the faces copied through
  const PointCloud back = ReadPly(out);
  EXPECT_NEAR(back.Point(0).y(), 5650000.654321, 1e-6);
  EXPECT_EQ(back.values[back.Index("red") + back.vertex_properties.size()], 12);
}

TEST(PointCloudPly, BinaryRoundTripsInBothByteOrders) {
  TempDir dir;
  for (auto format : {PointCloud::Format::kBinaryLittleEndian, PointCloud::Format::kBinaryBigEndian}) {
    PointCloud cloud;
    cloud.format = format;
    cloud.vertex_properties = {{"x", "float"}, {"y", "float"}, {"z", "float"}, {"intensity", "ushort"}};
    cloud.values = {1, 2, 3, 400, -4.5, 5.25, 6, 65535};
    cloud.tail_header = {"element extra 1", "property int n"};
    cloud.tail_data = std::string("\x01\x02\x03\x04", 4);
    const std::string path = (dir / "cloud.ply").string();
    WritePly(path, cloud);
    const PointCloud back = ReadPly(path);
    EXPECT_EQ(back.format, format);
    ASSERT_EQ(back.size(), 2u);
    EXPECT_EQ(back.vertex_properties[0].type, "double");  // coordinates are written as doubles
    EXPECT_EQ(back.vertex_properties[3].type, "ushort");
    EXPECT_EQ(back.values, cloud.values);
    EXPECT_EQ(back.tail_data, cloud.tail_data);
  }
}

TEST(PointCloudPly, ReadsSizedTypeNamesAndNormals) {
  TempDir dir;
  std::string data =
      "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float64 x\n"
      "property float64 y\nproperty float64 z\nproperty float32 nx\nproperty float32 ny\n"
      "property float32 nz\nend_header\n";
  const double xyz[3] = {1, 2, 3};
  const float n[3] = {0, 0, 1};
  data.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  data.append(reinterpret_cast<const char*>(n), sizeof n);
  const PointCloud cloud = ReadPly(WriteFile(dir / "n.ply", data).string());
  ASSERT_TRUE(cloud.HasNormals());
  EXPECT_EQ(cloud.Normal(0), Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(cloud.Point(0), Eigen::Vector3d(1, 2, 3));
}

TEST(PointCloudPly, BadFilesNameTheProblem) {
  TempDir dir;
  auto fatal = [&](const std::string& text) {
    try {
      ReadPly(WriteFile(dir / "bad.ply", text).string());
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "no InputError for " << text;
    return InputError("", 0, "", "");
  };
  EXPECT_EQ(fatal("PLY\n").line(), 1);
  EXPECT_EQ(
      fatal("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n").field(),
      "z");
  EXPECT_EQ(fatal("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                  "end_header\n1 2 3\n")
                .field(),
            "vertex");
  EXPECT_EQ(fatal("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
                  "end_header\n1 two 3\n")
                .line(),
            8);  // the data line after the 7 header lines
  EXPECT_EQ(fatal("ply\nformat binary_little_endian 1.0\nelement vertex 10\nproperty float x\nproperty float y\n"
                  "property float z\nend_header\nxyz")
                .field(),
            "vertex");
  EXPECT_EQ(fatal("ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int v\nelement vertex 1\n").line(), 3);
}

}  // namespace
}  // namespace seamap
