#pragma once
// The time stamps records carry (created/updated of a detection).
#include <string>

namespace seamap {

// Now as ISO 8601 UTC to the second, e.g. "2026-11-25T23:59:07Z".
std::string UtcNowIso8601();

}  // namespace seamap
