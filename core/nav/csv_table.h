#pragma once
// Line-based text tables as found in navigation logs: a header line, then one
// record per line. Handles a UTF-8 byte order mark, CRLF (or CR-only) line
// ends, blank lines and '#' comments, quoted fields ("a, b" and "" escapes),
// and a separator detected from the header: ',', ';', tab or runs of spaces.
#include <string>
#include <vector>

namespace seamap {

struct TextLine {
  int number = 0;  // 1-based line in the file
  std::string text;
};

// The file's meaningful lines (blank and '#' lines dropped, BOM and CR removed).
// Throws InputError when the file is missing, unreadable or has no such line.
std::vector<TextLine> ReadTextLines(const std::string& path);

// ' ' stands for "runs of whitespace".
char DetectSeparator(const std::string& header);

std::vector<std::string> SplitFields(const std::string& line, char separator);

struct CsvRow {
  int line = 0;
  std::vector<std::string> fields;
};

struct CsvTable {
  int header_line = 0;
  char separator = ',';
  std::vector<std::string> header;
  std::vector<CsvRow> rows;
};

CsvTable ParseCsv(const std::vector<TextLine>& lines);

// Trims spaces, tabs and no-break spaces at both ends.
std::string Trim(const std::string& text);

}  // namespace seamap
