#pragma once
// A CSV file of numbers read by column name, strictly: a missing column or a
// field that is not a number is an InputError naming the file, line and
// column. For small side files (georef's nav.csv, a truth table), not for
// navigation logs, whose reader skips and reports bad lines instead.
#include <map>
#include <string>
#include <vector>

namespace seamap {

using CsvNumbers = std::map<std::string, double>;  // column -> value

std::vector<CsvNumbers> ReadCsvNumbers(const std::string& path, const std::vector<std::string>& columns);

}  // namespace seamap
