// Randomised PLY files (tests/testing/fuzz.h, issue 33): headers with hostile
// counts and types, mangled bytes, truncated data, in every format. Each
// either reads into a cloud whose size the file can hold, or stops with an
// InputError naming the file. Never a crash, another exception, or an
// allocation beyond a few times the file's size.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "core/georef/point_cloud_ply.h"
#include "core/util/error.h"
#include "tests/testing/fuzz.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::Fuzz;
using testing::TempDir;

std::string Header(Fuzz& fuzz, const std::string& format, const std::string& count) {
  static const std::vector<std::string> kTypes = {"float", "double", "uchar", "int", "float64", "int8", "list", "bool"};
  std::string h = "ply\nformat " + format + " 1.0\n";
  if (fuzz.OneIn(3)) h += "comment UTM zone 52N\n";
  h += "element vertex " + count + "\n";
  for (const char* axis : {"x", "y", "z"})
    h += "property " + (fuzz.OneIn(8) ? fuzz.Pick(kTypes) : "double") + " " + axis + "\n";
  if (fuzz.OneIn(3)) h += "property uchar red\n";
  if (fuzz.OneIn(4))
    h += "element face " + (fuzz.OneIn(2) ? count : "1") + "\nproperty list uchar int vertex_indices\n";
  return h + "end_header\n";
}

TEST(PointCloudPlyFuzz, HostileCloudsReadWithinTheirSizeOrAreRefusedByName) {
  TempDir dir;
  Fuzz fuzz;
  const std::string path = (dir / "cloud.ply").string();
  static const std::vector<std::string> kFormats = {"ascii", "binary_little_endian", "binary_big_endian", "utf8"};
  static const std::vector<std::string> kCounts = {
      "0", "1",    "3",  "150000000", "-1", "4294967297", "1e8", "9223372036854775807", "99999999999999999999",
      "",  "0x10", "3.5"};
  while (fuzz.More()) {
    const std::string format = fuzz.Pick(kFormats);
    std::string text = Header(fuzz, format, fuzz.OneIn(2) ? fuzz.Pick(kCounts) : "3");
    const size_t vertices = 1 + fuzz.Below(4);
    for (size_t v = 0; v < vertices; ++v) {
      if (format == "ascii") {
        for (int k = 0; k < 4; ++k)
          text += (k ? " " : "") + (fuzz.OneIn(6) ? fuzz.HostileNumber() : std::to_string(v + k));
        text += "\n";
      } else {
        text += fuzz.Bytes(40);
      }
    }
    if (fuzz.OneIn(3)) text = fuzz.Mutate(text);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    SCOPED_TRACE("case " + std::to_string(fuzz.cases()) + ":\n" + text.substr(0, 400));
    try {
      const PointCloud cloud = ReadPly(path);
      // What was read fits in the file: at least one byte a value.
      EXPECT_LE(cloud.values.size(), text.size());
      EXPECT_EQ(cloud.values.size(), cloud.size() * cloud.vertex_properties.size());
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path) << e.what();
      EXPECT_LT(std::string(e.what()).size(), 600u) << "a message quotes the input whole";
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an InputError: " << e.what();
    }
  }
}

}  // namespace
}  // namespace seamap
