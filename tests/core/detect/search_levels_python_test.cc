// Issue 32: the training side (scripts/search_levels.py, used by
// train_detector.py) composes its windows at the levels `seamap detect`
// searches: both rules on the same inputs.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/detect/search_levels.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(SearchLevelsPython, ThePythonRuleChoosesTheCppLevels) {
  if (std::system("python3 -c '' >/dev/null 2>&1") != 0) GTEST_SKIP() << "no python3";
  const std::vector<std::vector<double>> size_sets = {{1.0, 1.2, 3.0, 1.5, 0.8},  // the shipped classes' largest sizes
                                                      {1.0, 1.2, 3.0, 1.5, 0.8, 1.1},  // with a drum learnt from review
                                                      {0.3},
                                                      {12.0, 0.05},
                                                      {2.0, 0, 0.6},
                                                      {0, 0}};
  std::ostringstream in;
  std::vector<std::vector<int>> expected;
  for (double lat : {0.0, 43.0, -61.5, 75.0})
    for (int base = 19; base <= 27; ++base)
      for (int min_zoom : {14, 23})
        for (const auto& sizes : size_sets) {
          in << lat << ' ' << base << ' ' << min_zoom;
          for (double s : sizes) in << ' ' << s;
          in << '\n';
          expected.push_back(ScaleMatchedZooms(sizes, base, min_zoom, lat, 256));
        }
  testing::TempDir dir;
  const std::string input = (dir / "in.txt").string(), output = (dir / "out.txt").string();
  std::ofstream(input) << in.str();
  const std::string cmd =
      "python3 " + std::string(SEAMAP_SOURCE_DIR) + "/scripts/search_levels.py <" + input + " >" + output;
  ASSERT_EQ(std::system(cmd.c_str()), 0) << cmd;
  std::ifstream out(output);
  std::string line;
  size_t i = 0, nonempty = 0;
  for (; std::getline(out, line); ++i) {
    ASSERT_LT(i, expected.size());
    std::istringstream z(line);
    std::vector<int> got;
    for (int v; z >> v;) got.push_back(v);
    EXPECT_EQ(got, expected[i]) << "input line " << i + 1;
    nonempty += !got.empty();
  }
  EXPECT_EQ(i, expected.size());
  EXPECT_GT(nonempty, expected.size() / 3);  // the comparison is not all empty lists
}

}  // namespace
}  // namespace seamap
