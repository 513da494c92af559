#include "core/nav/split_time.h"

#include <cmath>
#include <cstdio>

#include "core/nav/csv_table.h"
#include "core/nav/nav_values.h"

namespace seamap {
namespace {

bool Has(const std::map<std::string, std::string>& parts, const char* part) {
  return parts.count(part) > 0;
}

bool IsLeap(long year) {
  return (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
}

int DaysInMonth(long year, int month) {
  static const int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  return month == 2 && IsLeap(year) ? 29 : kDays[month - 1];
}

// A number within [low, high] (whole when `whole`); nullopt with *error naming the part.
std::optional<double> PartNumber(const std::string& part, const std::string& text, double low, double high, bool whole,
                                 bool high_open, bool decimal_comma, SplitTimeError* error) {
  std::string why;
  const auto value = ParseNumber(Trim(text), &why, decimal_comma);
  if (!value) {
    *error = {part, part + " " + why};
    return std::nullopt;
  }
  const bool inside = *value >= low && (high_open ? *value < high : *value <= high);
  if (!inside || (whole && std::floor(*value) != *value)) {
    *error = {part, part + " must be " + (whole ? "a whole number " : "a number ") + FormatNumber(low) +
                        (high_open ? " <= " + part + " < " + FormatNumber(high) : ".." + FormatNumber(high)) +
                        ", got " + FormatNumber(*value)};
    return std::nullopt;
  }
  return value;
}

// "2009-06-11", "2009/06/11" or "20090611": days since 1970.
std::optional<long> DateDays(const std::string& text, SplitTimeError* error) {
  const std::string date = Trim(text);
  int y = 0, m = 0, d = 0, consumed = 0;
  const bool read = (std::sscanf(date.c_str(), "%4d-%2d-%2d%n", &y, &m, &d, &consumed) == 3 ||
                     std::sscanf(date.c_str(), "%4d/%2d/%2d%n", &y, &m, &d, &consumed) == 3 ||
                     std::sscanf(date.c_str(), "%4d%2d%2d%n", &y, &m, &d, &consumed) == 3) &&
                    consumed == static_cast<int>(date.size());
  if (!read || y < 1900 || m < 1 || m > 12 || d < 1 || d > DaysInMonth(y, m)) {
    *error = {"date", "date must be a date YYYY-MM-DD (or YYYY/MM/DD, YYYYMMDD), got '" + Shorten(date) + "'"};
    return std::nullopt;
  }
  return DaysFromCivil(y, m, d);
}

}  // namespace

const std::vector<std::string>& SplitTimeParts() {
  static const std::vector<std::string> parts = {"year", "month", "day", "hour", "minute", "second", "date", "time"};
  return parts;
}

std::string SplitTimePartsProblem(const std::map<std::string, std::string>& parts) {
  for (const auto& [part, column] : parts) {
    bool known = false;
    for (const auto& name : SplitTimeParts()) known = known || name == part;
    if (!known)
      return "unknown part '" + Shorten(part) + "' (known: year, month, day, hour, minute, second, date, time)";
    if (Trim(column).empty()) return "part '" + part + "' names no column";
  }
  const bool ymd = Has(parts, "year") || Has(parts, "month") || Has(parts, "day");
  const bool hms = Has(parts, "hour") || Has(parts, "minute") || Has(parts, "second");
  if (Has(parts, "date") && ymd) return "give the date as 'date' or as 'year', 'month', 'day', not both";
  if (Has(parts, "time") && hms) return "give the time of day as 'time' or as 'hour', 'minute', 'second', not both";
  if (ymd && !(Has(parts, "year") && Has(parts, "month") && Has(parts, "day")))
    return "a date needs all of 'year', 'month', 'day'";
  if (!Has(parts, "time") && !(Has(parts, "hour") && Has(parts, "minute") && Has(parts, "second")))
    return "a time needs 'time' (hh:mm:ss.f) or all of 'hour', 'minute', 'second'";
  return "";
}

bool SplitTimeHasDate(const std::map<std::string, std::string>& parts) {
  return Has(parts, "date") || Has(parts, "year");
}

std::optional<double> ComposeSplitTime(const std::map<std::string, std::string>& values, bool decimal_comma,
                                       SplitTimeError* error) {
  for (const auto& [part, text] : values)
    if (Trim(text).empty()) {
      *error = {part, part + " is empty"};
      return std::nullopt;
    }
  double day_s = 0;
  if (Has(values, "date")) {
    const auto days = DateDays(values.at("date"), error);
    if (!days) return std::nullopt;
    day_s = *days * 86400.0;
  } else if (Has(values, "year")) {
    const auto y = PartNumber("year", values.at("year"), 1900, 9999, true, false, decimal_comma, error);
    if (!y) return std::nullopt;
    const auto m = PartNumber("month", values.at("month"), 1, 12, true, false, decimal_comma, error);
    if (!m) return std::nullopt;
    const long year = static_cast<long>(*y);
    const int month = static_cast<int>(*m);
    const auto d = PartNumber("day", values.at("day"), 1, DaysInMonth(year, month), true, false, decimal_comma, error);
    if (!d) return std::nullopt;
    day_s = DaysFromCivil(year, month, static_cast<unsigned>(*d)) * 86400.0;
  }
  if (Has(values, "time")) {
    const std::string text = Trim(values.at("time"));
    std::string why;
    const auto clock = text.find(':') != std::string::npos ? ParseTimeSeconds(text, &why, decimal_comma)
                                                           : ParseNumber(text, &why, decimal_comma);
    if (!clock || !(*clock >= 0 && *clock < 86401)) {
      *error = {"time",
                "time must be a time of day hh:mm:ss[.f] or seconds since midnight, got '" + Shorten(text) + "'"};
      return std::nullopt;
    }
    return day_s + *clock;
  }
  const auto h = PartNumber("hour", values.at("hour"), 0, 23, true, false, decimal_comma, error);
  if (!h) return std::nullopt;
  const auto mi = PartNumber("minute", values.at("minute"), 0, 59, true, false, decimal_comma, error);
  if (!mi) return std::nullopt;
  const auto s = PartNumber("second", values.at("second"), 0, 61, false, true, decimal_comma, error);
  if (!s) return std::nullopt;
  return day_s + *h * 3600 + *mi * 60 + *s;
}

}  // namespace seamap
