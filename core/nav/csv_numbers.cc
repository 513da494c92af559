#include "core/nav/csv_numbers.h"

#include <algorithm>

#include "core/nav/csv_table.h"
#include "core/nav/nav_values.h"
#include "core/util/error.h"

namespace seamap {

std::vector<CsvNumbers> ReadCsvNumbers(const std::string& path, const std::vector<std::string>& columns) {
  const CsvTable table = ParseCsv(ReadTextLines(path), path);
  std::vector<int> index;
  for (const auto& c : columns) {
    const auto it = std::find(table.header.begin(), table.header.end(), c);
    if (it == table.header.end()) throw InputError(path, table.header_line, c, "column missing");
    index.push_back(static_cast<int>(it - table.header.begin()));
  }
  std::vector<CsvNumbers> rows;
  for (const auto& row : table.rows) {
    CsvNumbers r;
    for (size_t k = 0; k < columns.size(); ++k) {
      std::string why;
      const auto v =
          index[k] < static_cast<int>(row.fields.size()) ? ParseNumber(Trim(row.fields[index[k]]), &why) : std::nullopt;
      if (!v) throw InputError(path, row.line, columns[k], "expected a number");
      r[columns[k]] = *v;
    }
    rows.push_back(r);
  }
  return rows;
}

}  // namespace seamap
