#include "core/util/json_file.h"

#include <sys/stat.h>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

std::string ErrorOf(const std::string& path, const std::string& what) {
  try {
    ReadJsonFile(path, what);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    return e.what();
  }
  return "no error";
}

TEST(ReadJsonFile, ParsesAFile) {
  TempDir dir;
  const std::string path = (dir / "a.json").string();
  testing::WriteFile(path, R"({"origin": [1, 2]})");
  EXPECT_EQ(ReadJsonFile(path, "survey description")["origin"][1], 2);
}

TEST(ReadJsonFile, NamesTheFileAndWhatItIsInEveryFailure) {
  TempDir dir;
  const std::string missing = (dir / "missing.json").string();
  EXPECT_EQ(ErrorOf(missing, "model"), missing + ": cannot read the model: no such file");
  EXPECT_EQ(ErrorOf(dir.path().string(), "model"), dir.path().string() + ": cannot read the model: not a regular file");
  const std::string fifo = (dir / "fifo.json").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(ErrorOf(fifo, "model"), fifo + ": cannot read the model: not a regular file");
  const std::string broken = (dir / "broken.json").string();
  testing::WriteFile(broken, "{\"a\": ");
  EXPECT_EQ(ErrorOf(broken, "rig's motion file").rfind(broken + ": cannot read the rig's motion file: not JSON: ", 0),
            0u);
}

}  // namespace
}  // namespace seamap
