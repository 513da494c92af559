#include "core/nav/csv_table.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/util/error.h"

namespace seamap {

std::string Trim(const std::string& text) {
  size_t begin = 0, end = text.size();
  auto space_at = [&](size_t i) { return text[i] == ' ' || text[i] == '\t'; };
  // U+00A0 (no-break space) is C2 A0 in UTF-8; spreadsheets like to emit it.
  auto nbsp_at = [&](size_t i) { return i + 1 < text.size() && text[i] == '\xC2' && text[i + 1] == '\xA0'; };
  while (begin < end) {
    if (space_at(begin))
      ++begin;
    else if (begin + 1 < end && nbsp_at(begin))
      begin += 2;
    else
      break;
  }
  while (end > begin) {
    if (space_at(end - 1))
      --end;
    else if (end >= begin + 2 && nbsp_at(end - 2))
      end -= 2;
    else
      break;
  }
  return text.substr(begin, end - begin);
}

std::vector<TextLine> ReadTextLines(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw InputError(path, 0, "", "is a folder, expected a navigation text file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", std::string("cannot open file: ") + std::strerror(errno));
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "", "cannot read file");
  std::string text = buffer.str();
  if (text.empty()) throw InputError(path, 0, "", "file is empty");
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  // Old Mac files end lines with CR alone.
  const char eol = text.find('\n') == std::string::npos ? '\r' : '\n';

  std::vector<TextLine> lines;
  int number = 0;
  size_t start = 0;
  while (start <= text.size()) {
    size_t stop = text.find(eol, start);
    if (stop == std::string::npos) stop = text.size();
    std::string line = text.substr(start, stop - start);
    ++number;
    start = stop + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    lines.push_back({number, line});
  }
  if (lines.empty()) throw InputError(path, 0, "", "file has no header line (only blank lines and # comments)");
  return lines;
}

char DetectSeparator(const std::string& header) {
  int commas = 0, semicolons = 0, tabs = 0;
  bool quoted = false;
  for (char c : header) {
    if (c == '"') quoted = !quoted;
    if (quoted) continue;
    commas += c == ',';
    semicolons += c == ';';
    tabs += c == '\t';
  }
  if (commas == 0 && semicolons == 0 && tabs == 0) return ' ';
  if (tabs >= commas && tabs >= semicolons) return '\t';
  return semicolons > commas ? ';' : ',';
}

std::vector<std::string> SplitFields(const std::string& line, char separator) {
  std::vector<std::string> fields;
  const bool whitespace = separator == ' ';
  std::string field;
  bool quoted = false, pending = false;
  auto is_sep = [&](char c) { return whitespace ? (c == ' ' || c == '\t') : c == separator; };
  auto finish = [&] {
    fields.push_back(Trim(field));
    field.clear();
    pending = false;
  };
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c != '"')
        field += c;
      else if (i + 1 < line.size() && line[i + 1] == '"')
        field += line[++i];
      else
        quoted = false;
    } else if (c == '"' && Trim(field).empty()) {
      field.clear();
      quoted = pending = true;
    } else if (is_sep(c)) {
      if (whitespace && !pending) continue;  // runs of spaces are one separator
      finish();
    } else {
      field += c;
      pending = true;
    }
  }
  if (!whitespace || pending) finish();
  return fields;
}

CsvTable ParseCsv(const std::vector<TextLine>& lines) {
  CsvTable table;
  if (lines.empty()) return table;
  table.header_line = lines[0].number;
  table.separator = DetectSeparator(lines[0].text);
  table.header = SplitFields(lines[0].text, table.separator);
  // "a,b,c," has three columns; rows may or may not repeat the trailing separator.
  while (!table.header.empty() && table.header.back().empty()) table.header.pop_back();
  for (size_t i = 1; i < lines.size(); ++i)
    table.rows.push_back({lines[i].number, SplitFields(lines[i].text, table.separator)});
  return table;
}

}  // namespace seamap
