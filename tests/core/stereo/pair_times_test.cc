// A stereo pair's time: from its name (a UTC stamp, or seconds marked as
// such) or from a table, with errors naming the file, line and column.
#include "core/stereo/pair_times.h"

#include <fstream>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(PairTimes, NamesGiveSecondsOrAUtcStamp) {
  EXPECT_EQ(PairTimeFromName("dive_0012.500"), 12.5);
  EXPECT_EQ(PairTimeFromName("t812"), 812);
  EXPECT_EQ(PairTimeFromName("pass3_t812.25"), 812.25);
  EXPECT_EQ(PairTimeFromName("pair_40s"), 40);
  EXPECT_EQ(PairTimeFromName("1700000000.25"), 1700000000.25);
  EXPECT_EQ(PairTimeFromName("1700000000"), 1700000000);
  // A real vehicle's image name: 2009-06-11 06:54:20.385 UTC.
  ASSERT_TRUE(PairTimeFromName("PR_20090611_065420_385_LC16.png"));
  EXPECT_NEAR(*PairTimeFromName("PR_20090611_065420_385_LC16.png"), 1244703260.385, 1e-6);
  EXPECT_NEAR(*PairTimeFromName("cam_20090611T065420.5"), 1244703260.5, 1e-6);
  // A counter is not a clock; nor is a name without a number.
  EXPECT_FALSE(PairTimeFromName("ap_001"));
  EXPECT_FALSE(PairTimeFromName("wellhead"));
  EXPECT_FALSE(PairTimeFromName("dive_12.5.3"));
  EXPECT_FALSE(PairTimeFromName("cam_20091399_065420"));  // month 13
}

TEST(PairTimes, ATableFindsPairsByNameOrEitherImage) {
  testing::TempDir dir;
  const std::string path = (dir / "times.csv").string();
  std::ofstream(path) << "leftimage;time_s\nA_left.png;10.5\nB;2009-06-11T06:54:20.385Z\n";
  const PairTimes times = PairTimes::Read(path);
  EXPECT_EQ(times.size(), 2u);
  EXPECT_EQ(times.Find("A", "/x/A_left.png", "/x/A_right.png"), 10.5);
  ASSERT_TRUE(times.Find("B", "/x/left/B.png", "/x/right/B.png"));
  EXPECT_NEAR(*times.Find("B", "/x/left/B.png", "/x/right/B.png"), 1244703260.385, 1e-6);
  EXPECT_FALSE(times.Find("C", "/x/C_left.png", "/x/C_right.png"));
}

void ExpectRefused(const std::string& text, int line, const std::string& field, const std::string& needle) {
  testing::TempDir dir;
  const std::string path = (dir / "t.csv").string();
  std::ofstream(path) << text;
  try {
    PairTimes::Read(path);
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path);
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(PairTimes, BadTablesAreRefusedNamingWhere) {
  ExpectRefused("image,when\nA,1\n", 1, "time_s", "time_s or time");
  ExpectRefused("file,time_s\nA,1\n", 1, "image", "pair's name");
  ExpectRefused("image,time_s\nA,1\nB,later\n", 3, "time_s", "'later'");
  ExpectRefused("image,time_s\nA,1\nA,2\n", 3, "image", "listed twice");
  ExpectRefused("image,time_s\nA\n", 2, "", "expected 2 fields");
  ExpectRefused("image,time_s\n," + std::string(200, '9') + "x\n", 2, "image", "pair's name");
}

}  // namespace
}  // namespace seamap
