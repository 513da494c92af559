#include "core/enhance/param_check.h"

#include <cstdio>

#include "core/util/error.h"

namespace seamap {

void RequireParam(bool ok, const std::string& field, const std::string& expected, double value) {
  if (ok) return;
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  throw InputError("", 0, field, "expected " + expected + ", got " + text);
}

}  // namespace seamap
