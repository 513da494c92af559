#include "core/georef/georef_inputs.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/geo/local_frame.h"
#include "core/nav/column_aliases.h"
#include "core/nav/csv_table.h"
#include "core/nav/nav_reader.h"
#include "core/nav/nav_values.h"
#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

struct Table {
  CsvTable csv;
  ColumnMap columns;
  bool decimal_comma = false;
};

Table ReadTable(const std::string& path) {
  Table t;
  t.csv = ParseCsv(ReadTextLines(path));
  t.columns = MapColumns(t.csv.header, {}, path, t.csv.header_line);
  t.decimal_comma = t.csv.separator != ',';
  return t;
}

// The number in an optional column; nullopt when the column is absent or the
// row is short. Sets *why when present but not a number.
std::optional<double> Optional(const Table& t, const CsvRow& row, const std::string& column, std::string* why) {
  if (!t.columns.Has(column)) return std::nullopt;
  const size_t index = t.columns.index.at(column);
  if (index >= row.fields.size() || Trim(row.fields[index]).empty()) return std::nullopt;
  std::string reason;
  auto value = ParseNumber(Trim(row.fields[index]), &reason, t.decimal_comma);
  if (!value) *why = column + " " + reason;
  return value;
}

}  // namespace

BuoyLog ReadBuoyLog(const std::string& path) {
  NavReadOptions options;
  options.require_altitude = false;
  const NavTable table = ReadNavigation(path, options);
  if (!table.has_times)
    throw InputError(path, 0, "time_s",
                     "the buoy's fixes need a time column; accepted names: " + AcceptedNames("time_s"));
  BuoyLog log;
  log.rejected = table.rejected;
  log.warnings = table.warnings;

  // The GPS quality columns, by line.
  const Table extras = ReadTable(path);
  std::map<int, const CsvRow*> rows;
  for (const CsvRow& row : extras.csv.rows) rows[row.line] = &row;

  const LocalFrame frame(table.origin);
  for (const NavRecord& record : table.records) {
    if (!record.time_s) {
      log.rejected.push_back({path, record.line, "time_s", "time_s is missing"});
      continue;
    }
    BuoyFixRecord fix;
    fix.time_s = *record.time_s;
    fix.position = frame.ToLatLon({record.pose.east_m, record.pose.north_m});
    fix.line = record.line;
    auto it = rows.find(record.line);
    if (it != rows.end()) {
      std::string why;
      const auto sigma = Optional(extras, *it->second, "sigma_m", &why);
      const auto hdop = Optional(extras, *it->second, "hdop", &why);
      const auto quality = Optional(extras, *it->second, "fix_quality", &why);
      if (!why.empty()) {
        log.rejected.push_back({path, record.line, why.substr(0, why.find(' ')), why});
        continue;
      }
      if (quality && *quality == 0) {
        log.rejected.push_back({path, record.line, "fix_quality", "fix_quality 0: no fix"});
        continue;
      }
      if ((sigma && !(*sigma > 0)) || (hdop && !(*hdop > 0))) {
        log.rejected.push_back(
            {path, record.line, sigma && !(*sigma > 0) ? "sigma_m" : "hdop", "sigma_m and hdop must be > 0"});
        continue;
      }
      fix.sigma_m = sigma.value_or(0);
      fix.hdop = hdop.value_or(0);
    }
    log.fixes.push_back(fix);
  }
  std::stable_sort(log.rejected.begin(), log.rejected.end(),
                   [](const Rejection& a, const Rejection& b) { return a.line < b.line; });
  if (log.fixes.size() < 2)
    throw InputError(path, 0, "",
                     "fewer than 2 usable GPS fixes (" + std::to_string(log.rejected.size()) + " rows rejected)");
  return log;
}

LatLon MedianPosition(const BuoyLog& log) {
  std::vector<double> lats, lons;
  for (const auto& f : log.fixes) lats.push_back(f.position.lat), lons.push_back(f.position.lon);
  return {Median(lats), Median(lons)};
}

BuoyTrack MakeBuoyTrack(const BuoyLog& log, const LocalFrame& frame) {
  std::vector<BuoyFix> fixes;
  for (const auto& f : log.fixes) {
    const LocalXY xy = frame.FromLatLon(f.position);
    fixes.push_back({f.time_s, {xy.east, xy.north}, f.sigma_m, f.hdop, f.line});
  }
  return BuoyTrack(std::move(fixes));
}

namespace {

DepthLog ReadTimeSeries(const std::string& path, const std::string& column, bool positive) {
  const Table t = ReadTable(path);
  for (const std::string& name : {std::string("time_s"), column})
    if (!t.columns.Has(name))
      throw InputError(path, t.csv.header_line, name, "no " + name + " column; accepted names: " + AcceptedNames(name));
  DepthLog log;
  if (!t.columns.unknown.empty()) {
    std::string names;
    for (const auto& u : t.columns.unknown) names += (names.empty() ? "" : ", ") + u;
    log.warnings.push_back(path + ":" + std::to_string(t.csv.header_line) + ": ignoring unknown columns: " + names);
  }
  const size_t time_index = t.columns.index.at("time_s"), value_index = t.columns.index.at(column);
  for (const CsvRow& row : t.csv.rows) {
    if (std::max(time_index, value_index) >= row.fields.size()) {
      log.rejected.push_back({path, row.line, "", "line has " + std::to_string(row.fields.size()) + " fields"});
      continue;
    }
    std::string why;
    const auto time = ParseTimeSeconds(Trim(row.fields[time_index]), &why, t.decimal_comma);
    if (!time) {
      log.rejected.push_back({path, row.line, "time_s", "time_s " + why});
      continue;
    }
    const auto value = ParseNumber(Trim(row.fields[value_index]), &why, t.decimal_comma);
    if (!value) {
      log.rejected.push_back({path, row.line, column, column + " " + why});
      continue;
    }
    if (positive ? !(*value > 0) : *value < 0) {
      log.rejected.push_back(
          {path, row.line, column,
           column + (positive ? " must be > 0, got " : " must be >= 0, got ") + FormatNumber(*value)});
      continue;
    }
    log.samples.push_back({*time, *value});
  }
  if (log.samples.empty()) {
    if (log.rejected.empty()) throw InputError(path, t.csv.header_line, "", "no " + column + " rows after the header");
    const Rejection& first = log.rejected.front();
    throw InputError(path, first.line, first.field, "no usable " + column + " row; first problem: " + first.reason);
  }
  return log;
}

}  // namespace

DepthLog ReadDepthLog(const std::string& path) {
  return ReadTimeSeries(path, "depth_m", false);
}

DepthLog ReadAltitudeLog(const std::string& path) {
  return ReadTimeSeries(path, "altitude_m", true);
}

}  // namespace seamap
