#pragma once
// Parsing of single navigation values, with the reason a value is refused
// worded for the user ("is not a number: 'abc'").
#include <optional>
#include <string>

namespace seamap {

// A finite number. Accepts a leading '+', the Unicode minus sign and other
// dashes (U+2010..U+2015, U+FE63, U+FF0D) as '-', and a decimal comma when
// decimal_comma is set (';' or tab separated files). On failure returns
// nullopt and sets *why.
std::optional<double> ParseNumber(const std::string& text, std::string* why, bool decimal_comma = false);

// Seconds: a plain number, an ISO 8601 date-time (2023-05-01T12:00:00.5Z,
// offsets allowed; seconds since 1970 UTC) or a time of day hh:mm:ss[.f].
std::optional<double> ParseTimeSeconds(const std::string& text, std::string* why, bool decimal_comma = false);

struct UtmZone {
  int zone = 0;
  std::optional<bool> north;  // when the text names the hemisphere
};

// "52", "52N", "52 S", "52north". N/S are read as the hemisphere; other
// letters as the MGRS latitude band (C..M south, P..X north).
std::optional<UtmZone> ParseUtmZone(const std::string& text, std::string* why);

// Days since 1970-01-01 of a proleptic Gregorian date (month 1..12, day 1..31).
long DaysFromCivil(long y, unsigned m, unsigned d);

// 3.5, 1e-07, 1234567.25: short and exact enough for messages.
std::string FormatNumber(double value);

}  // namespace seamap
