// `since` past any change number (issue 33): 1e19 or 1e300 is after every
// change, so nothing passes; a plain cast made it INT64_MIN (everything).
#include <gtest/gtest.h>

#include <limits>

#include "core/mission/detection_error.h"
#include "core/mission/detection_filter.h"

namespace seamap {
namespace {

DetectionFilter Since(const std::string& text) {
  return ParseDetectionFilter(std::nullopt, std::nullopt, std::nullopt, text);
}

TEST(DetectionFilterSince, PastTheLargestSeqNothingPasses) {
  Detection d;
  d.seq = std::numeric_limits<int64_t>::max() - 1;
  for (const std::string text : {"1e19", "1e300", "9223372036854775808", "1.7976931348623157e308"}) {
    const DetectionFilter f = Since(text);
    ASSERT_TRUE(f.since) << text;
    EXPECT_EQ(*f.since, std::numeric_limits<int64_t>::max()) << text;
    EXPECT_FALSE(Passes(f, d)) << text;
  }
  EXPECT_EQ(*Since("9007199254740992").since, int64_t{9007199254740992});
  d.seq = 3;
  EXPECT_TRUE(Passes(Since("2"), d));
  EXPECT_FALSE(Passes(Since("3"), d));
}

TEST(DetectionFilterSince, WhatIsNoChangeNumberIsRefusedNamingSince) {
  for (const std::string text : {"1e400", "-1", "-1e19", "1.5", "nan", "inf", "x"}) {
    try {
      Since(text);
      ADD_FAILURE() << text << " accepted";
    } catch (const DetectionError& e) {
      EXPECT_EQ(e.field(), "since") << text;
    }
  }
}

}  // namespace
}  // namespace seamap
