#include "core/util/progress.h"

#include <unistd.h>

#include <algorithm>

namespace seamap {

ProgressBar::ProgressBar(std::string unit, long total, bool enabled)
    : unit_(std::move(unit)),
      total_(total),
      enabled_(enabled),
      tty_(isatty(fileno(stderr))),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

double ProgressBar::Rate() const {
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  return s > 0 ? done_ / s : 0;
}

void ProgressBar::Update(long done, const std::string& extra) {
  done_ = done;
  Draw(false, extra);
}

void ProgressBar::Finish(const std::string& extra) {
  Draw(true, extra);
  if (enabled_ && tty_) std::fputc('\n', stderr);
}

void ProgressBar::Draw(bool force, const std::string& extra) {
  if (!enabled_) return;
  auto now = std::chrono::steady_clock::now();
  long percent = total_ > 0 ? done_ * 100 / total_ : 0;
  if (tty_) {
    if (!force && now - last_draw_ < std::chrono::milliseconds(100)) return;
    const int width = 30;
    int filled = total_ > 0 ? static_cast<int>(std::min<long>(width, done_ * width / total_)) : 0;
    std::fprintf(stderr, "\r[%s%s] %ld/%ld %s  %.1f %s/s  %s\x1b[K", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), done_, total_, unit_.c_str(), Rate(), unit_.c_str(),
                 extra.c_str());
  } else {
    // Logs (CI, pipes): one line per 10 %.
    if (percent / 10 == last_logged_percent_ / 10 && (!force || percent == last_logged_percent_)) return;
    last_logged_percent_ = percent;
    std::fprintf(stderr, "%3ld%% %ld/%ld %s  %.1f %s/s  %s\n", percent, done_, total_, unit_.c_str(), Rate(),
                 unit_.c_str(), extra.c_str());
  }
  std::fflush(stderr);
  last_draw_ = now;
}

}  // namespace seamap
