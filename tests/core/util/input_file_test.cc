#include "core/util/input_file.h"

#include <sys/stat.h>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

std::string Refusal(const std::string& path, int64_t max_bytes = 0) {
  try {
    RegularFileBytes(path, "keyframe file", "--keyframes", max_bytes);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.field(), "--keyframes");
    return e.detail();
  }
  ADD_FAILURE() << path << " accepted";
  return "";
}

TEST(RegularFileBytes, SizesRegularFilesAndRefusesTheRestByName) {
  testing::TempDir dir;
  const std::string file = testing::WriteFile(dir / "k.txt", "12345").string();
  EXPECT_EQ(RegularFileBytes(file, "keyframe file"), 5);
  EXPECT_EQ(Refusal(file, 4), "cannot read the keyframe file: 5 bytes, over the limit of 4");
  EXPECT_EQ(Refusal((dir / "none").string()), "cannot read the keyframe file: no such file");
  EXPECT_EQ(Refusal("/dev/zero"), "cannot read the keyframe file: not a regular file (a character device)");
  EXPECT_EQ(Refusal(dir.path().string()), "cannot read the keyframe file: not a regular file (a folder)");
  const std::string fifo = (dir / "fifo").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(Refusal(fifo), "cannot read the keyframe file: not a regular file (a FIFO)");
}

}  // namespace
}  // namespace seamap
