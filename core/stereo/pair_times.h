#pragma once
// When each stereo pair of a dive was taken, so that its pose can be read off
// the vehicle's trajectory: from a table (`--pair-times FILE`: a column naming
// the pair, `image`/`name`/`pair`/`left`/`leftimage`, and `time_s`/`time`,
// seconds in the trajectory's clock) or from the pair's name:
//   * a UTC timestamp YYYYMMDD_HHMMSS[_mmm] (or YYYYMMDDTHHMMSS[.fff]), as
//     real vehicles name their images (PR_20090611_065420_385_LC16.png):
//     seconds since 1970-01-01 UTC;
//   * or seconds: the name's last '_' field, written t12.5, 12.5s or 12.500
//     (a point, a leading t or a trailing s), or a name that is only a number
//     (dive_0012.500, t812, 1700000000.25). ap_001 has no time: a counter is not a clock.
#include <map>
#include <optional>
#include <string>

namespace seamap {

// The time in a pair's name (NAME of NAME_left.png, or a file name), if any.
std::optional<double> PairTimeFromName(const std::string& name);

class PairTimes {
 public:
  // Reads the table; InputError naming the file, line and column for what
  // does not fit (no name or time column, a time that is not a number, the same
  // pair twice).
  static PairTimes Read(const std::string& path);

  // The time of the pair NAME (also found by the file name of either image,
  // with or without its extension).
  std::optional<double> Find(const std::string& name, const std::string& left_file,
                             const std::string& right_file) const;
  size_t size() const { return times_.size(); }

 private:
  std::map<std::string, double> times_;
};

}  // namespace seamap
