#pragma once
// What this process has used so far.
#include <cstdint>

namespace seamap {

// Peak resident memory, bytes.
int64_t PeakRssBytes();
// CPU time (user + system, all threads), seconds.
double ProcessCpuSeconds();

}  // namespace seamap
