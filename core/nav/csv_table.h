#pragma once
// Line-based text tables as found in navigation logs: a header line, then one
// record per line. Handles a UTF-8 byte order mark, CRLF (or CR-only) line
// ends, blank lines and '#' comments, quoted fields ("a, b" and "" escapes),
// and a separator detected from the header: ',', ';', tab or runs of spaces.
#include <cstddef>
#include <string>
#include <vector>

namespace seamap {

// Navigation lines are short (a hundred bytes); these bounds keep a broken or
// hostile file (a 10 MB line, a binary file) from costing more than its own
// size: a longer line is not kept, and is reported instead of its fields.
constexpr size_t kMaxLineBytes = 65536;
constexpr size_t kMaxFieldBytes = 4096;  // a path name's length (PATH_MAX)

struct TextLine {
  int number = 0;  // 1-based line in the file
  std::string text;
  size_t overlong = 0;  // the line's length when over kMaxLineBytes (text is then empty)
};

// The file's meaningful lines (blank and '#' lines dropped, BOM and CR removed).
// Throws InputError when the file is missing, unreadable or has no such line,
// or when its first such line (the header) is over kMaxLineBytes.
std::vector<TextLine> ReadTextLines(const std::string& path);

// ' ' stands for "runs of whitespace".
char DetectSeparator(const std::string& header);

std::vector<std::string> SplitFields(const std::string& line, char separator);

struct CsvRow {
  int line = 0;
  std::vector<std::string> fields;
  std::string problem;  // why the line cannot be read (too long, a field too long); fields empty
};

struct CsvTable {
  int header_line = 0;
  char separator = ',';
  std::vector<std::string> header;
  std::vector<CsvRow> rows;
};

// Throws InputError(path, line, ...) when a header field is over kMaxFieldBytes.
CsvTable ParseCsv(const std::vector<TextLine>& lines, const std::string& path = "");

// Trims spaces, tabs and no-break spaces at both ends.
std::string Trim(const std::string& text);

// The text for a message: as is when short, else its start and its length.
std::string Shorten(const std::string& text, size_t max = 64);

}  // namespace seamap
