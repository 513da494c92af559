#include "core/util/process_stats.h"

#include <sys/resource.h>

namespace seamap {
namespace {

rusage SelfUsage() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage;
}

}  // namespace

int64_t PeakRssBytes() {
  return static_cast<int64_t>(SelfUsage().ru_maxrss) * 1024;
}

double ProcessCpuSeconds() {
  const rusage usage = SelfUsage();
  auto seconds = [](const timeval& t) { return t.tv_sec + t.tv_usec / 1e6; };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

}  // namespace seamap
