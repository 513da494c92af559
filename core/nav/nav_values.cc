#include "core/nav/nav_values.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "core/nav/csv_table.h"

namespace seamap {
namespace {

// Replaces UTF-8 dashes that spreadsheets and word processors put in place of '-'.
std::string AsciiMinus(const std::string& text) {
  static const char* const kDashes[] = {
      "\xE2\x88\x92",                                  // U+2212 minus sign
      "\xE2\x80\x90", "\xE2\x80\x91", "\xE2\x80\x92",  // hyphen, non-breaking hyphen, figure dash
      "\xE2\x80\x93", "\xE2\x80\x94", "\xE2\x80\x95",  // en dash, em dash, horizontal bar
      "\xEF\xB9\xA3", "\xEF\xBC\x8D"};                 // small and full-width hyphen-minus
  std::string out = text;
  if (std::all_of(text.begin(), text.end(), [](char c) { return static_cast<unsigned char>(c) < 0x80; }))
    return out;  // plain ASCII, the usual case
  for (const char* dash : kDashes)
    for (size_t at = out.find(dash); at != std::string::npos; at = out.find(dash, at)) out.replace(at, 3, "-");
  return out;
}

// hh:mm:ss[.f] at text[pos]; advances pos.
std::optional<double> ParseClock(const std::string& text, size_t& pos) {
  int h = 0, m = 0, consumed = 0;
  if (std::sscanf(text.c_str() + pos, "%2d:%2d%n", &h, &m, &consumed) != 2) return std::nullopt;
  pos += consumed;
  double s = 0;
  if (pos < text.size() && text[pos] == ':') {
    size_t end = pos + 1;
    while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '.')) ++end;
    auto [ptr, ec] = std::from_chars(text.data() + pos + 1, text.data() + end, s);
    if (ec != std::errc() || ptr != text.data() + end) return std::nullopt;
    pos = end;
  }
  if (h > 24 || m > 59 || s >= 61) return std::nullopt;
  return h * 3600.0 + m * 60.0 + s;
}

std::optional<double> ParseIsoTime(const std::string& text) {
  size_t pos = 0;
  double date_s = 0;
  int y = 0, mo = 0, d = 0, consumed = 0;
  if (std::sscanf(text.c_str(), "%4d-%2d-%2d%n", &y, &mo, &d, &consumed) == 3 && consumed == 10) {
    if (mo < 1 || mo > 12 || d < 1 || d > 31) return std::nullopt;
    date_s = DaysFromCivil(y, mo, d) * 86400.0;
    pos = 10;
    if (pos == text.size()) return date_s;
    if (text[pos] != 'T' && text[pos] != 't' && text[pos] != ' ') return std::nullopt;
    ++pos;
  }
  auto clock = ParseClock(text, pos);
  if (!clock) return std::nullopt;
  double offset_s = 0;
  if (pos < text.size() && (text[pos] == 'Z' || text[pos] == 'z')) {
    ++pos;
  } else if (pos < text.size() && (text[pos] == '+' || text[pos] == '-')) {
    int oh = 0, om = 0, n = 0;
    const char* rest = text.c_str() + pos + 1;
    if (std::sscanf(rest, "%2d:%2d%n", &oh, &om, &n) != 2 && std::sscanf(rest, "%2d%2d%n", &oh, &om, &n) != 2)
      return std::nullopt;
    offset_s = (text[pos] == '-' ? -1 : 1) * (oh * 3600.0 + om * 60.0);
    pos += 1 + n;
  }
  if (pos != text.size()) return std::nullopt;
  return date_s + *clock - offset_s;
}

}  // namespace

// H. Hinnant's algorithm.
long DaysFromCivil(long y, unsigned m, unsigned d) {
  y -= m <= 2;
  const long era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<long>(doe) - 719468;
}

std::string FormatNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

std::optional<double> ParseNumber(const std::string& raw, std::string* why, bool decimal_comma) {
  std::string text = AsciiMinus(Trim(raw));
  if (text.empty()) {
    *why = "is empty";
    return std::nullopt;
  }
  if (decimal_comma && text.find(',') != std::string::npos && text.find('.') == std::string::npos)
    text[text.find(',')] = '.';
  const size_t start = text[0] == '+' && text.size() > 1 && text[1] != '-' ? 1 : 0;
  double value = 0;
  auto [ptr, ec] = std::from_chars(text.data() + start, text.data() + text.size(), value);
  if (ec == std::errc::result_out_of_range) {
    *why = "is out of range: '" + Shorten(raw) + "'";
    return std::nullopt;
  }
  if (ec != std::errc() || ptr != text.data() + text.size() || start == text.size()) {
    *why = "is not a number: '" + Shorten(raw) + "'";
    return std::nullopt;
  }
  if (std::isnan(value)) {
    *why = "is not a number (NaN)";
    return std::nullopt;
  }
  if (!std::isfinite(value)) {
    *why = "is not finite ('" + Shorten(raw) + "')";
    return std::nullopt;
  }
  return value;
}

std::optional<double> ParseTimeSeconds(const std::string& raw, std::string* why, bool decimal_comma) {
  const std::string text = Trim(raw);
  if (text.find(':') != std::string::npos) {
    if (auto seconds = ParseIsoTime(text)) return seconds;
    *why = "is not a time: '" + Shorten(raw) + "' (expected seconds, hh:mm:ss or 2023-05-01T12:00:00Z)";
    return std::nullopt;
  }
  return ParseNumber(text, why, decimal_comma);
}

std::optional<UtmZone> ParseUtmZone(const std::string& raw, std::string* why) {
  const std::string text = Trim(raw);
  UtmZone out;
  size_t pos = 0;
  while (pos < text.size() && std::isdigit(static_cast<unsigned char>(text[pos])))
    out.zone = out.zone * 10 + (text[pos++] - '0');
  std::string rest;
  for (size_t i = pos; i < text.size(); ++i)
    if (text[i] != ' ') rest += static_cast<char>(std::toupper(static_cast<unsigned char>(text[i])));
  if (pos == 0 || pos > 2 || out.zone < 1 || out.zone > 60) {
    *why = "is not a UTM zone 1..60: '" + Shorten(raw) + "'";
    return std::nullopt;
  }
  if (rest == "N" || rest == "NORTH")
    out.north = true;
  else if (rest == "S" || rest == "SOUTH")
    out.north = false;
  else if (rest.size() == 1 && rest[0] >= 'C' && rest[0] <= 'X' && rest[0] != 'I' && rest[0] != 'O')
    out.north = rest[0] >= 'N';
  else if (!rest.empty()) {
    *why = "has an unknown hemisphere or band: '" + Shorten(raw) + "' (expected e.g. 52, 52N or 52S)";
    return std::nullopt;
  }
  return out;
}

}  // namespace seamap
