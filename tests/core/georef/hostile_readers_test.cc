// Issue 33, row 10: the point cloud and keyframe readers check what a header
// declares against the file's size before allocating, and refuse inputs that
// are not regular files (/dev/zero never ends, a FIFO blocks) by name.
#include <sys/stat.h>

#include <gtest/gtest.h>

#include "core/georef/point_cloud_ply.h"
#include "core/georef/tum_trajectory.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;
using ::seamap::testing::WriteFile;

template <typename F>
InputError ExpectInputError(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return InputError("", 0, "", "");
  }
  ADD_FAILURE() << "no error";
  return InputError("", 0, "", "");
}

const char* kXyz = "property float x\nproperty float y\nproperty float z\n";

TEST(HostilePly, HeaderDeclaringMoreVerticesThanTheFileHoldsIsRefusedBeforeAllocating) {
  TempDir dir;
  for (const std::string format : {"binary_little_endian", "binary_big_endian", "ascii"}) {
    // The 117-byte header: 1.5e8 vertices would be 3.6 GB of doubles.
    const std::string path =
        WriteFile(dir / ("big_" + format + ".ply"),
                  "ply\nformat " + format + " 1.0\nelement vertex 150000000\n" + kXyz + "end_header\n1 2 3\n")
            .string();
    const InputError e = ExpectInputError([&] { ReadPly(path); });
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), 3) << e.what();
    EXPECT_EQ(e.field(), "vertex");
    EXPECT_NE(std::string(e.what()).find("declares 150000000 vertices"), std::string::npos) << e.what();
  }
  // A count near the top of a long overflows no product.
  const std::string huge = WriteFile(dir / "huge.ply",
                                     "ply\nformat binary_little_endian 1.0\nelement vertex "
                                     "9223372036854775807\n" +
                                         std::string(kXyz) + "end_header\n")
                               .string();
  EXPECT_EQ(ExpectInputError([&] { ReadPly(huge); }).field(), "vertex");
}

TEST(HostilePly, CountsThatFitStillRead) {
  TempDir dir;
  const std::string path = WriteFile(dir / "ok.ply", "ply\nformat ascii 1.0\nelement vertex 2\n" + std::string(kXyz) +
                                                         "end_header\n1 2 3\n4 5 6\n")
                               .string();
  EXPECT_EQ(ReadPly(path).size(), 2u);
  const std::string empty = WriteFile(dir / "empty.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 0\n" +
                                                             std::string(kXyz) + "end_header\n")
                                .string();
  EXPECT_EQ(ReadPly(empty).size(), 0u);
}

TEST(HostileReaders, DevZeroAndFifosAreRefusedByName) {
  TempDir dir;
  const std::string fifo = (dir / "fifo").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& path : {std::string("/dev/zero"), fifo, dir.path().string()}) {
    const InputError ply = ExpectInputError([&] { ReadPly(path); });
    EXPECT_EQ(ply.file(), path);
    EXPECT_NE(std::string(ply.what()).find("not a regular file"), std::string::npos) << ply.what();
    const InputError tum = ExpectInputError([&] { ReadTumTrajectory(path); });
    EXPECT_EQ(tum.file(), path);
    EXPECT_NE(std::string(tum.what()).find("not a regular file"), std::string::npos) << tum.what();
  }
}

}  // namespace
}  // namespace seamap
