#pragma once
// Parameter validation shared by the enhancement operations.
#include <string>

namespace seamap {

// Throws InputError("", 0, field, "expected <expected>, got <value>") unless ok.
// field is "<op>.<param>", e.g. "clahe.clip_limit".
void RequireParam(bool ok, const std::string& field, const std::string& expected, double value);

}  // namespace seamap
