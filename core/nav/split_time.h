#pragma once
// A time written over several columns, as vehicle logs do: year, month, day,
// hour, minute, second (ACFR's AUV logs), or a date and a time of day.
// Composed into seconds since 1970-01-01 UTC when the date is there, else
// into seconds since midnight (the reader carries those across midnight).
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace seamap {

// The parts a time may be split into, in the order messages list them.
const std::vector<std::string>& SplitTimeParts();

// Why a set of parts cannot make a time ("" when it can): a time of day
// (time, or hour+minute+second) is needed; a date is date, or year+month+day;
// a part may not be given twice (date with year, time with hour).
std::string SplitTimePartsProblem(const std::map<std::string, std::string>& parts);

// True when the parts include a date (seconds since 1970, not since midnight).
bool SplitTimeHasDate(const std::map<std::string, std::string>& parts);

struct SplitTimeError {
  std::string part;    // the part whose value is wrong, e.g. "month"
  std::string reason;  // e.g. "must be a whole number 1..12, got 13"
};

// values: part -> the field as written. nullopt with *error set when a value
// is empty, not a number, or out of its range (second in [0, 61) for leap
// seconds; day within its month).
std::optional<double> ComposeSplitTime(const std::map<std::string, std::string>& values, bool decimal_comma,
                                       SplitTimeError* error);

}  // namespace seamap
