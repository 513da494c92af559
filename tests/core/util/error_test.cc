#include "core/util/error.h"

#include <gtest/gtest.h>

namespace seamap {
namespace {

TEST(InputError, NamesFileLineAndField) {
  InputError e("nav.csv", 12, "altitude_m", "must be > 0, got -1");
  EXPECT_STREQ(e.what(), "nav.csv:12: field 'altitude_m': must be > 0, got -1");
  EXPECT_EQ(e.line(), 12);
  EXPECT_EQ(e.field(), "altitude_m");
}

TEST(InputError, OmitsWhatIsUnknown) {
  EXPECT_STREQ(InputError("camera.json", 0, "", "not JSON").what(), "camera.json: not JSON");
  EXPECT_STREQ(InputError("", 0, "--port", "expected a number").what(), "--port: expected a number");
}

}  // namespace
}  // namespace seamap
