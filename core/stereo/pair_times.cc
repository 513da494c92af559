#include "core/stereo/pair_times.h"

#include <cmath>
#include <ctime>
#include <filesystem>
#include <regex>
#include <vector>

#include "core/nav/csv_table.h"
#include "core/nav/nav_values.h"
#include "core/util/error.h"

namespace seamap {
namespace {

std::optional<double> UtcStamp(const std::string& name) {
  static const std::regex stamp(R"((\d{4})(\d{2})(\d{2})[_T](\d{2})(\d{2})(\d{2})(?:[_.](\d{1,6}))?)");
  std::smatch m;
  if (!std::regex_search(name, m, stamp)) return std::nullopt;
  std::tm t{};
  t.tm_year = std::stoi(m[1]) - 1900;
  t.tm_mon = std::stoi(m[2]) - 1;
  t.tm_mday = std::stoi(m[3]);
  t.tm_hour = std::stoi(m[4]);
  t.tm_min = std::stoi(m[5]);
  t.tm_sec = std::stoi(m[6]);
  if (t.tm_mon < 0 || t.tm_mon > 11 || t.tm_mday < 1 || t.tm_mday > 31 || t.tm_hour > 23 || t.tm_min > 59 ||
      t.tm_sec > 60)
    return std::nullopt;
  double seconds = static_cast<double>(timegm(&t));
  if (m[7].matched) seconds += std::stod("0." + m[7].str());
  return seconds;
}

std::string Stem(const std::string& file) {
  return std::filesystem::path(file).stem().string();
}

}  // namespace

std::optional<double> PairTimeFromName(const std::string& raw) {
  std::string name = raw;
  for (const char* ext : {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".PNG", ".JPG"})
    if (name.size() > std::string(ext).size() &&
        name.compare(name.size() - std::string(ext).size(), std::string::npos, ext) == 0)
      name.resize(name.size() - std::string(ext).size());
  if (auto stamp = UtcStamp(name)) return stamp;
  const size_t cut = name.find_last_of('_');
  const std::string field = cut == std::string::npos ? name : name.substr(cut + 1);
  static const std::regex seconds(R"((t?)(\d+(\.\d+)?)(s?))");
  std::smatch m;
  if (!std::regex_match(field, m, seconds)) return std::nullopt;
  const bool marked = m[1].length() > 0 || m[3].matched || m[4].length() > 0;
  if (!marked && cut != std::string::npos) return std::nullopt;  // ap_001: a counter
  const double t = std::stod(m[2]);
  return std::isfinite(t) ? std::optional<double>(t) : std::nullopt;
}

PairTimes PairTimes::Read(const std::string& path) {
  const CsvTable table = ParseCsv(ReadTextLines(path), path);
  int name_col = -1, time_col = -1;
  for (size_t i = 0; i < table.header.size(); ++i) {
    const std::string h = Trim(table.header[i]);
    if (name_col < 0 && (h == "image" || h == "name" || h == "pair" || h == "left" || h == "leftimage"))
      name_col = static_cast<int>(i);
    if (time_col < 0 && (h == "time_s" || h == "time")) time_col = static_cast<int>(i);
  }
  if (name_col < 0 || time_col < 0)
    throw InputError(path, table.header_line, name_col < 0 ? "image" : "time_s",
                     "expected a header with the pair's name (image, name, pair, left or leftimage) and its time "
                     "(time_s or time, seconds in the trajectory's clock)");
  PairTimes times;
  for (const CsvRow& row : table.rows) {
    if (!row.problem.empty()) throw InputError(path, row.line, "", row.problem);
    const size_t need = static_cast<size_t>(std::max(name_col, time_col)) + 1;
    if (row.fields.size() < need)
      throw InputError(path, row.line, "",
                       "expected " + std::to_string(need) + " fields, got " + std::to_string(row.fields.size()));
    const std::string name = Trim(row.fields[name_col]);
    const std::string text = Trim(row.fields[time_col]);
    std::string why;
    const std::optional<double> t = ParseTimeSeconds(text, &why);
    if (name.empty()) throw InputError(path, row.line, table.header[name_col], "expected the pair's name, got nothing");
    if (!t || !std::isfinite(*t))
      throw InputError(path, row.line, table.header[time_col],
                       "expected seconds, got '" + Shorten(text, 100) + "'" + (why.empty() ? "" : ": " + why));
    if (!times.times_.emplace(name, *t).second)
      throw InputError(path, row.line, table.header[name_col], "pair '" + Shorten(name, 100) + "' is listed twice");
  }
  return times;
}

std::optional<double> PairTimes::Find(const std::string& name, const std::string& left_file,
                                      const std::string& right_file) const {
  for (const std::string& key : {name, std::filesystem::path(left_file).filename().string(), Stem(left_file),
                                 std::filesystem::path(right_file).filename().string(), Stem(right_file)}) {
    auto it = times_.find(key);
    if (it != times_.end()) return it->second;
  }
  return std::nullopt;
}

}  // namespace seamap
