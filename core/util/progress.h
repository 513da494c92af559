#pragma once
// A one-line progress bar on stderr ("[#####.....] 120/400 frames  37.2 frames/s"),
// redrawn at most 10 times a second; plain lines when stderr is not a terminal.
#include <chrono>
#include <cstdio>
#include <string>

namespace seamap {

class ProgressBar {
 public:
  ProgressBar(std::string unit, long total, bool enabled = true);
  // Sets the number of items done; `extra` is appended (e.g. "tiles 1234").
  void Update(long done, const std::string& extra = "");
  // Final redraw and newline.
  void Finish(const std::string& extra = "");
  double Rate() const;  // items per second so far

 private:
  void Draw(bool force, const std::string& extra);
  std::string unit_;
  long total_;
  long done_ = 0;
  bool enabled_;
  bool tty_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  long last_logged_percent_ = -1;
};

}  // namespace seamap
