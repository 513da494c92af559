#include "core/nav/csv_table.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/util/error.h"
#include "core/util/input_file.h"

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
  // /dev/zero or a FIFO would never end (a missing file is reported by the open below).
  if (std::filesystem::exists(path, ec)) RegularFileBytes(path, "text file");
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
    const size_t length = stop - start;
    const size_t first = start;
    ++number;
    start = stop + 1;
    if (length > kMaxLineBytes) {  // not copied: only its length is reported
      const size_t text_at = text.find_first_not_of(" \t", first);
      if (text_at < stop && text[text_at] == '#') continue;  // a long comment harms no one
      if (lines.empty())
        throw InputError(path, number, "",
                         "line is " + std::to_string(length) + " bytes long (limit " + std::to_string(kMaxLineBytes) +
                             "): not a header line; is this a navigation text file?");
      lines.push_back({number, "", length});
      continue;
    }
    std::string line = text.substr(first, length);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    lines.push_back({number, line});
  }
  if (lines.empty()) throw InputError(path, 0, "", "file has no header line (only blank lines and # comments)");
  return lines;
}

std::string Shorten(const std::string& text, size_t max) {
  if (text.size() <= max) return text;
  return text.substr(0, max) + "... (" + std::to_string(text.size()) + " bytes)";
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
  bool blank = true;  // field holds only spaces so far (kept, not recomputed: lines of quotes stay linear)
  auto is_sep = [&](char c) { return whitespace ? (c == ' ' || c == '\t') : c == separator; };
  auto add = [&](char c) {
    field += c;
    blank = blank && (c == ' ' || c == '\t' || c == '\xC2' || c == '\xA0');
  };
  auto finish = [&] {
    fields.push_back(Trim(field));
    field.clear();
    pending = false;
    blank = true;
  };
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c != '"')
        add(c);
      else if (i + 1 < line.size() && line[i + 1] == '"')
        add(line[++i]);
      else
        quoted = false;
    } else if (c == '"' && blank) {
      field.clear();
      quoted = pending = true;
    } else if (is_sep(c)) {
      if (whitespace && !pending) continue;  // runs of spaces are one separator
      finish();
    } else {
      add(c);
      pending = true;
    }
  }
  if (!whitespace || pending) finish();
  return fields;
}

namespace {

// The first field over kMaxFieldBytes, or fields.size().
size_t OverlongField(const std::vector<std::string>& fields) {
  size_t i = 0;
  while (i < fields.size() && fields[i].size() <= kMaxFieldBytes) ++i;
  return i;
}

std::string TooLong(const std::string& what, size_t length, size_t limit) {
  return what + " is " + std::to_string(length) + " bytes long (limit " + std::to_string(limit) + ")";
}

}  // namespace

CsvTable ParseCsv(const std::vector<TextLine>& lines, const std::string& path) {
  CsvTable table;
  if (lines.empty()) return table;
  table.header_line = lines[0].number;
  table.separator = DetectSeparator(lines[0].text);
  table.header = SplitFields(lines[0].text, table.separator);
  if (size_t i = OverlongField(table.header); i < table.header.size())
    throw InputError(path, table.header_line, "",
                     TooLong("column " + std::to_string(i + 1) + "'s name", table.header[i].size(), kMaxFieldBytes));
  // "a,b,c," has three columns; rows may or may not repeat the trailing separator.
  while (!table.header.empty() && table.header.back().empty()) table.header.pop_back();
  for (size_t i = 1; i < lines.size(); ++i) {
    CsvRow row{lines[i].number, {}, ""};
    if (lines[i].overlong) {
      row.problem = TooLong("line", lines[i].overlong, kMaxLineBytes);
    } else {
      row.fields = SplitFields(lines[i].text, table.separator);
      if (size_t f = OverlongField(row.fields); f < row.fields.size()) {
        row.problem = TooLong("field " + std::to_string(f + 1), row.fields[f].size(), kMaxFieldBytes);
        row.fields.clear();
      }
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

}  // namespace seamap
