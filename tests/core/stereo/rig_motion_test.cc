// Issue 33, row 14: the rig's motion file (stereo-locate --motion) refuses
// what no navigation measures (a translation of 1e300 m, a sigma of 1e300)
// naming the file and field; and randomised motion files (tests/testing/fuzz.h)
// either read into finite poses or stop with an InputError naming the file.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "core/stereo/object_locator.h"
#include "core/util/error.h"
#include "tests/testing/fuzz.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::Fuzz;
using testing::TempDir;

std::string Motion(const std::string& t0, const std::string& t1, const std::string& sigma_m = "0.002") {
  return R"({"world_from_camera": {"pair_000": [[1, 0, 0, )" + t0 + R"(], [0, 1, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]],
  "pair_001": [[0, -1, 0, )" +
         t1 + R"(], [1, 0, 0, 0.5], [0, 0, 1, 3], [0, 0, 0, 1]]},
 "sigma_m": )" +
         sigma_m + R"(, "sigma_deg": 0.02})";
}

InputError ReadError(const std::string& path) {
  try {
    ReadRigMotion(path);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error";
  return InputError("", 0, "", "");
}

TEST(RigMotion, ReadsPlausiblePoses) {
  TempDir dir;
  const std::string path = (dir / "motion.json").string();
  std::ofstream(path) << Motion("1", "500000.25");  // UTM eastings are fine
  const RigMotion m = ReadRigMotion(path);
  ASSERT_EQ(m.world_from_camera.size(), 2u);
  EXPECT_EQ(m.world_from_camera.at("pair_001").translation().x(), 500000.25);
}

TEST(RigMotion, HugeTranslationsAndSigmasAreRefusedNamingTheField) {
  TempDir dir;
  const std::string path = (dir / "motion.json").string();
  std::ofstream(path) << Motion("1", "1e300");
  const InputError e = ReadError(path);
  EXPECT_EQ(e.file(), path);
  EXPECT_EQ(e.field(), "world_from_camera.pair_001") << e.what();
  EXPECT_NE(std::string(e.what()).find("translation x = 1e+300 m is out of range"), std::string::npos) << e.what();

  std::ofstream(path, std::ios::trunc) << Motion("1", "2", "1e300");
  EXPECT_EQ(ReadError(path).field(), "sigma_m");

  // A pair name of 1 MB is quoted cut short.
  std::ofstream(path, std::ios::trunc) << R"({"world_from_camera": {")" << std::string(1 << 20, 'p') << R"(": 1}})";
  EXPECT_LT(std::string(ReadError(path).what()).size(), 400u);
}

// The valid file with each number replaced, one time in `odds`, by a hostile value.
std::string WithHostileNumbers(Fuzz& fuzz, const std::string& text, size_t odds) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    const bool starts_number =
        (std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '-') &&
        (i == 0 || (!std::isalnum(static_cast<unsigned char>(text[i - 1])) && text[i - 1] != '_'));
    if (!starts_number) {
      out += text[i++];
      continue;
    }
    size_t end = i + 1;
    while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '.' ||
                                 text[end] == 'e' || text[end] == '-' || text[end] == '+'))
      ++end;
    out += fuzz.OneIn(odds) ? fuzz.HostileNumber() : text.substr(i, end - i);
    i = end;
  }
  return out;
}

TEST(RigMotionFuzz, HostileMotionFilesReadFiniteOrAreRefusedByName) {
  TempDir dir;
  Fuzz fuzz;
  const std::string path = (dir / "motion.json").string();
  const std::string valid = Motion("1", "2");
  while (fuzz.More()) {
    std::string text = WithHostileNumbers(fuzz, valid, 5);
    if (fuzz.OneIn(3)) text = fuzz.Mutate(text);
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    SCOPED_TRACE("case " + std::to_string(fuzz.cases()) + ":\n" + text.substr(0, 600));
    try {
      const RigMotion m = ReadRigMotion(path);
      for (const auto& [pair, pose] : m.world_from_camera) {
        EXPECT_TRUE(pose.matrix().allFinite()) << pair;
        EXPECT_LE(pose.translation().cwiseAbs().maxCoeff(), 1e7) << pair;
      }
      EXPECT_TRUE(m.sigma_m > 0 && m.sigma_m <= 1000);
      EXPECT_TRUE(m.sigma_deg > 0 && m.sigma_deg <= 180);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an InputError: " << e.what();
    }
  }
}

}  // namespace
}  // namespace seamap
