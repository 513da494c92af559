#include "core/nav/nav_reader.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <set>

#include "core/geo/local_frame.h"
#include "core/nav/column_aliases.h"
#include "core/nav/csv_table.h"
#include "core/nav/nav_limits.h"
#include "core/nav/nav_values.h"
#include "core/nav/split_time.h"
#include "core/util/error.h"

namespace seamap {
namespace {

// One line's values by canonical column; only the columns the line has.
struct RawRow {
  int line = 0;
  std::map<std::string, std::string> fields;
};

// Rows of either format in one shape, before any value is parsed.
struct Source {
  int header_line = 0;
  std::vector<std::string> found;  // column names as written, for messages
  std::set<std::string> columns;   // canonical columns present
  bool decimal_comma = false;
  std::vector<RawRow> rows;
  std::vector<Rejection> rejected;
};

enum class PositionKind { kLocal, kGeographic, kUtm };

// A line's problem; caught per line and turned into a Rejection.
struct Reject {
  std::string field;
  std::string reason;
};

// Names as written in the file, each shortened for the message.
std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + Shorten(item);
  return out;
}

std::string Where(const std::string& path, int line) {
  return path + (line > 0 ? ":" + std::to_string(line) : "");
}

// ---- CSV ----------------------------------------------------------------

// A time split over columns (options.time_columns): where each part is, and
// the day carried across midnight when the parts have no date.
struct SplitTimeReader {
  std::map<std::string, int> index;  // part -> column
  bool has_date = false;
  double day_offset_s = 0;
  std::optional<double> previous_s;
  int midnight_line = 0;  // first line carried into the next day
};

// Finds the time parts' columns; they are no longer unknown, and a column
// an alias took for something else (e.g. 'time' as time_s) is theirs.
SplitTimeReader MapTimeColumns(const CsvTable& table, const NavReadOptions& options, const std::string& path,
                               ColumnMap* map, std::vector<std::string>* warnings) {
  SplitTimeReader reader;
  reader.has_date = SplitTimeHasDate(options.time_columns);
  std::set<std::string> used;
  for (const auto& [part, name] : options.time_columns) {
    const std::string wanted = NormalizeColumnName(name);
    int found = -1;
    for (size_t i = 0; i < table.header.size() && found < 0; ++i)
      if (NormalizeColumnName(table.header[i]) == wanted) found = static_cast<int>(i);
    if (found < 0)
      throw InputError(path, table.header_line, "navigation.time_columns." + part,
                       "column '" + Shorten(name) + "' (the time's " + part +
                           ") is not in the header; found: " + Join(table.header));
    reader.index[part] = found;
    used.insert(table.header[found]);
  }
  map->unknown.erase(std::remove_if(map->unknown.begin(), map->unknown.end(),
                                    [&](const std::string& name) { return used.count(name) > 0; }),
                     map->unknown.end());
  // A second time column an alias took as a repeat of time_s is ignored for the same reason.
  for (auto it = map->repeated.begin(); it != map->repeated.end();) {
    if (used.count(*it) == 0 && CanonicalColumn(*it) != "time_s") {
      ++it;
      continue;
    }
    if (used.count(*it) == 0)
      warnings->push_back(Where(path, table.header_line) + ": ignoring column '" + Shorten(*it) +
                          "': the time comes from navigation.time_columns");
    it = map->repeated.erase(it);
  }
  for (auto it = map->index.begin(); it != map->index.end();) {
    const bool part_column = used.count(table.header[it->second]) > 0;
    if (!part_column && it->first != "time_s") {
      ++it;
      continue;
    }
    if (!part_column)
      warnings->push_back(Where(path, table.header_line) + ": ignoring column '" + Shorten(table.header[it->second]) +
                          "': the time comes from navigation.time_columns");
    it = map->index.erase(it);
  }
  return reader;
}

// The row's time in seconds as text (time_s), or a Rejection's reason.
std::optional<std::string> ComposeRowTime(SplitTimeReader* reader, const CsvRow& row, bool decimal_comma,
                                          SplitTimeError* error) {
  std::map<std::string, std::string> values;
  for (const auto& [part, index] : reader->index) values[part] = row.fields[index];
  auto time_s = ComposeSplitTime(values, decimal_comma, error);
  if (!time_s) return std::nullopt;
  if (!reader->has_date) {
    // A time of day only: a drop of more than half a day is the next day.
    if (reader->previous_s && *time_s + reader->day_offset_s < *reader->previous_s - 43200) {
      reader->day_offset_s += 86400;
      if (!reader->midnight_line) reader->midnight_line = row.line;
    }
    *time_s += reader->day_offset_s;
    reader->previous_s = *time_s;
  }
  char text[64];
  std::snprintf(text, sizeof text, "%.6f", *time_s);
  return std::string(text);
}

Source ReadCsv(const std::string& path, const std::vector<TextLine>& lines, const NavReadOptions& options,
               std::vector<std::string>* warnings) {
  const CsvTable table = ParseCsv(lines, path);
  ColumnMap map = MapColumns(table.header, options.columns, path, table.header_line);
  std::optional<SplitTimeReader> split_time;
  if (!options.time_columns.empty()) split_time = MapTimeColumns(table, options, path, &map, warnings);
  Source source;
  source.header_line = table.header_line;
  source.found = table.header;
  source.decimal_comma = table.separator != ',';
  for (const auto& entry : map.index) source.columns.insert(entry.first);
  if (split_time) source.columns.insert("time_s");
  if (!map.unknown.empty())
    warnings->push_back(Where(path, table.header_line) + ": ignoring unknown columns: " + Join(map.unknown));
  if (!map.repeated.empty())
    warnings->push_back(Where(path, table.header_line) +
                        ": ignoring columns that repeat an earlier one: " + Join(map.repeated));

  const size_t width = table.header.size();
  for (const CsvRow& row : table.rows) {
    if (!row.problem.empty()) {
      source.rejected.push_back({path, row.line, "", row.problem});
      continue;
    }
    if (row.fields.size() < width) {
      const std::string missing = table.header[row.fields.size()];
      std::string field = missing;
      for (const auto& [canonical, index] : map.index)
        if (index == static_cast<int>(row.fields.size())) field = canonical;
      source.rejected.push_back({path, row.line, field,
                                 "line has " + std::to_string(row.fields.size()) + " fields but the header has " +
                                     std::to_string(width) + "; missing column '" + Shorten(missing) + "'"});
      continue;
    }
    const bool extra =
        std::any_of(row.fields.begin() + width, row.fields.end(), [](const std::string& f) { return !f.empty(); });
    if (extra) {
      source.rejected.push_back(
          {path, row.line, "",
           "line has " + std::to_string(row.fields.size()) + " fields but the header has " + std::to_string(width)});
      continue;
    }
    RawRow raw{row.line, {}};
    for (const auto& [canonical, index] : map.index) raw.fields[canonical] = row.fields[index];
    if (split_time) {
      SplitTimeError error;
      const auto time_s = ComposeRowTime(&*split_time, row, source.decimal_comma, &error);
      if (!time_s) {
        source.rejected.push_back({path, row.line, error.part, error.reason});
        continue;
      }
      raw.fields["time_s"] = *time_s;
    }
    source.rows.push_back(std::move(raw));
  }
  if (split_time && split_time->midnight_line)
    warnings->push_back(Where(path, split_time->midnight_line) +
                        ": the time of day passes midnight; read as the next day (navigation.time_columns has no "
                        "date)");
  return source;
}

// ---- the seed paper's text format ---------------------------------------
//   09204051.jpg X(m): 1.0, Y(m): 2.0, Alt(m): 1.6, Heading(deg): 30.0,

bool IsSeedText(const std::string& line) {
  std::string squeezed;
  for (char c : line)
    if (c != ' ' && c != '\t') squeezed += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return squeezed.find("x(m):") != std::string::npos;
}

Source ReadSeedText(const std::string& path, const std::vector<TextLine>& lines, std::vector<std::string>* warnings) {
  Source source;
  source.header_line = lines.front().number;
  source.columns.insert("image");
  std::set<std::string> unknown;
  for (const TextLine& line : lines) {
    if (line.overlong) {
      source.rejected.push_back(
          {path, line.number, "",
           "line is " + std::to_string(line.overlong) + " bytes long (limit " + std::to_string(kMaxLineBytes) + ")"});
      continue;
    }
    const std::string text = Trim(line.text);
    const size_t name_end = text.find_first_of(" \t");
    RawRow raw{line.number, {{"image", text.substr(0, name_end)}}};
    const std::string rest = name_end == std::string::npos ? "" : text.substr(name_end);
    bool bad = false;
    size_t start = 0;
    while (start <= rest.size() && !bad) {
      size_t stop = rest.find(',', start);
      if (stop == std::string::npos) stop = rest.size();
      const std::string piece = Trim(rest.substr(start, stop - start));
      start = stop + 1;
      if (piece.empty()) continue;
      const size_t colon = piece.find(':');
      if (colon == std::string::npos) {
        source.rejected.push_back(
            {path, line.number, "", "cannot read '" + Shorten(piece) + "' (expected KEY(unit): VALUE)"});
        bad = true;
        break;
      }
      const std::string key = Trim(piece.substr(0, colon));
      const std::string canonical = CanonicalColumn(key);
      if (canonical.empty() || canonical == "image") {
        unknown.insert(key);
        continue;
      }
      raw.fields[canonical] = piece.substr(colon + 1);
      source.columns.insert(canonical);
      if (std::find(source.found.begin(), source.found.end(), key) == source.found.end()) source.found.push_back(key);
    }
    if (!bad) source.rows.push_back(std::move(raw));
  }
  if (!unknown.empty())
    warnings->push_back(path + ": ignoring unknown keys: " + Join({unknown.begin(), unknown.end()}));
  return source;
}

// ---- header checks ------------------------------------------------------

std::string FoundList(const Source& source) {
  return source.found.empty() ? "(none)" : Join(source.found);
}

void RequirePair(const Source& source, const std::string& path, const char* a, const char* b) {
  const bool has_a = source.columns.count(a) > 0, has_b = source.columns.count(b) > 0;
  if (has_a == has_b) return;
  const std::string missing = has_a ? b : a;
  throw InputError(path, source.header_line, missing,
                   "found '" + std::string(has_a ? a : b) + "' but no '" + missing + "' column; found: " +
                       FoundList(source) + "; accepted names for " + missing + ": " + AcceptedNames(missing));
}

PositionKind ChoosePosition(const Source& source, const std::string& path, const NavReadOptions& options,
                            std::vector<std::string>* warnings) {
  auto has = [&](const char* name) { return source.columns.count(name) > 0; };
  const bool geographic = has("lat") && has("lon");
  const bool utm = has("easting") && has("northing");
  const bool local = has("x_m") && has("y_m");
  if (!geographic && !utm && !local) {
    RequirePair(source, path, "lat", "lon");
    RequirePair(source, path, "easting", "northing");
    RequirePair(source, path, "x_m", "y_m");
    throw InputError(path, source.header_line, "position",
                     "no position columns; found: " + FoundList(source) +
                         "; expected x_m,y_m (metres east/north of --origin), lat,lon (WGS84 degrees) or "
                         "easting,northing (UTM). Accepted names: x_m: " +
                         AcceptedNames("x_m") + "; y_m: " + AcceptedNames("y_m") + "; lat: " + AcceptedNames("lat") +
                         "; lon: " + AcceptedNames("lon") + "; easting: " + AcceptedNames("easting") +
                         "; northing: " + AcceptedNames("northing"));
  }
  // Absolute positions win: they stay right whatever --origin is.
  const PositionKind kind = geographic ? PositionKind::kGeographic : utm ? PositionKind::kUtm : PositionKind::kLocal;
  if ((geographic && utm) || (kind != PositionKind::kLocal && local))
    warnings->push_back(Where(path, source.header_line) + ": positions read from " +
                        (geographic ? "lat, lon" : "easting, northing") + "; other position columns ignored");
  if (kind == PositionKind::kLocal && !options.origin)
    throw InputError(path, source.header_line, "x_m", "local positions need --origin LAT,LON");
  if (kind == PositionKind::kUtm && !has("utm_zone") && !options.utm_zone)
    throw InputError(path, source.header_line, "utm_zone",
                     "UTM easting/northing need a zone: add a utm_zone column (e.g. 52N) or give --utm-zone ZONE");
  if (!has("altitude_m") && options.require_altitude)
    throw InputError(
        path, source.header_line, "altitude_m",
        "no altitude column; found: " + FoundList(source) + "; accepted names: " + AcceptedNames("altitude_m"));
  if (!has("image") && !has("time_s"))
    throw InputError(path, source.header_line, "image",
                     "no image or time column; found: " + FoundList(source) +
                         "; accepted names: image: " + AcceptedNames("image") + "; time_s: " + AcceptedNames("time_s") +
                         "; other names: the config's navigation.columns, a split time: navigation.time_columns");
  return kind;
}

// ---- one line's values --------------------------------------------------

struct Parsed {
  NavRecord record;                          // pose in local metres when !geo
  std::optional<LatLon> geo;                 // geographic position, converted once the origin is known
  std::optional<double> heading_as_written;  // before any unit conversion: to tell radians from degrees
};

class RowParser {
 public:
  RowParser(const RawRow& row, bool decimal_comma) : row_(row), decimal_comma_(decimal_comma) {}

  // nullopt when the column is absent; throws Reject when present but empty or bad.
  std::optional<std::string> Text(const std::string& field) const {
    auto it = row_.fields.find(field);
    if (it == row_.fields.end()) return std::nullopt;
    const std::string value = Trim(it->second);
    if (value.empty()) throw Reject{field, field + " is empty"};
    return value;
  }

  std::optional<double> Number(const std::string& field) const {
    auto text = Text(field);
    if (!text) return std::nullopt;
    std::string why;
    auto value = ParseNumber(*text, &why, decimal_comma_);
    if (!value) throw Reject{field, field + " " + why};
    return value;
  }

  double Required(const std::string& field) const {
    auto value = Number(field);
    if (!value) throw Reject{field, field + " is missing"};
    return *value;
  }

  std::optional<double> Time() const {
    auto text = Text("time_s");
    if (!text) return std::nullopt;
    std::string why;
    auto value = ParseTimeSeconds(*text, &why, decimal_comma_);
    if (!value) throw Reject{"time_s", "time_s " + why};
    return value;
  }

  bool Has(const std::string& field) const { return row_.fields.count(field) > 0; }
  const std::string& Raw(const std::string& field) const { return row_.fields.at(field); }

 private:
  const RawRow& row_;
  bool decimal_comma_;
};

void CheckRange(const std::string& field, double value, double low, double high, bool open) {
  const bool inside = open ? (value > low && value < high) : (value >= low && value <= high);
  if (!inside)
    throw Reject{field, field + " must be within " + (open ? "(" : "[") + FormatNumber(low) + ", " +
                            FormatNumber(high) + (open ? ")" : "]") + ", got " + FormatNumber(value)};
}

// |value| <= limit: finite values that would place a frame nowhere sensible.
void CheckMagnitude(const std::string& field, double value, double limit, const char* unit) {
  if (std::fabs(value) > limit)
    throw Reject{field,
                 field + " must be within +-" + FormatNumber(limit) + " " + unit + ", got " + FormatNumber(value)};
}

LatLon UtmPosition(const RowParser& row, const NavReadOptions& options) {
  const double easting = row.Required("easting");
  const double northing = row.Required("northing");
  CheckRange("easting", easting, 0, 1e6, true);
  CheckRange("northing", northing, 0, 1e7, false);
  int zone = options.utm_zone.value_or(0);
  bool north = options.utm_north;
  if (auto text = row.Text("utm_zone")) {
    std::string why;
    auto parsed = ParseUtmZone(*text, &why);
    if (!parsed) throw Reject{"utm_zone", "utm_zone " + why};
    zone = parsed->zone;
    north = parsed->north.value_or(north);
  }
  try {
    return UtmToLatLon(easting, northing, zone, north);
  } catch (const InputError& e) {
    const std::string field = e.field().empty() ? "utm_zone" : e.field();
    throw Reject{field, field + ": " + e.detail()};
  }
}

Parsed ParseRow(const RawRow& raw, PositionKind kind, const NavReadOptions& options, bool decimal_comma) {
  const RowParser row(raw, decimal_comma);
  Parsed out;
  NavRecord& record = out.record;
  record.line = raw.line;
  // A row may lack its image when the time series is denser than the photos.
  if (row.Has("image")) {
    record.image = Trim(row.Raw("image"));
    if (record.image.empty() && !row.Has("time_s")) throw Reject{"image", "image is empty"};
  }
  record.time_s = row.Time();
  if (record.time_s) CheckMagnitude("time_s", *record.time_s, nav_limits::kMaxAbsTimeS, "s");

  VehiclePose& pose = record.pose;
  if (kind == PositionKind::kLocal) {
    pose.east_m = row.Required("x_m");
    CheckMagnitude("x_m", pose.east_m, nav_limits::kMaxLocalM, "m");
    pose.north_m = row.Required("y_m");
    CheckMagnitude("y_m", pose.north_m, nav_limits::kMaxLocalM, "m");
  } else {
    LatLon ll;
    if (kind == PositionKind::kGeographic) {
      ll.lat = row.Required("lat");
      ll.lon = row.Required("lon");
    } else {
      ll = UtmPosition(row, options);
    }
    CheckRange("lat", ll.lat, -90, 90, false);
    CheckRange("lon", ll.lon, -180, 180, false);
    out.geo = ll;
  }
  pose.altitude_m = options.require_altitude ? row.Required("altitude_m") : row.Number("altitude_m").value_or(0);
  if (options.require_altitude && !(pose.altitude_m > 0))
    throw Reject{"altitude_m", "altitude_m must be > 0, got " + FormatNumber(pose.altitude_m)};
  if (pose.altitude_m > nav_limits::kMaxAltitudeM)
    throw Reject{"altitude_m", "altitude_m must be at most " + FormatNumber(nav_limits::kMaxAltitudeM) +
                                   " m above the seabed, got " + FormatNumber(pose.altitude_m)};
  pose.depth_m = row.Number("depth_m").value_or(0);
  CheckRange("depth_m", pose.depth_m, nav_limits::kMinDepthM, nav_limits::kMaxDepthM, false);
  const double to_deg = options.angle_unit == AngleUnit::kRadians ? 180 / M_PI : 1.0;
  out.heading_as_written = row.Number("heading_deg");
  const double heading = out.heading_as_written.value_or(0) * to_deg;
  pose.heading_deg = std::fmod(heading, 360.0);
  if (pose.heading_deg < 0) pose.heading_deg += 360.0;
  if (pose.heading_deg >= 360.0) pose.heading_deg = 0;  // -1e-17 + 360 rounds to 360
  const double attitude = nav_limits::kMaxAttitudeDeg;
  pose.pitch_deg = row.Number("pitch_deg").value_or(0) * to_deg;
  CheckRange("pitch_deg", pose.pitch_deg, -attitude, attitude, true);
  pose.roll_deg = row.Number("roll_deg").value_or(0) * to_deg;
  CheckRange("roll_deg", pose.roll_deg, -attitude, attitude, true);
  return out;
}

// A time_s column that is empty on every row is no time column: trajectory.csv
// keeps its fixed header for navigation that had no times. (An empty time
// among timed rows is still refused, line by line.)
void DropEmptyTimeColumn(Source* source) {
  if (!source->columns.count("time_s") || source->rows.empty()) return;
  for (const RawRow& row : source->rows) {
    auto it = row.fields.find("time_s");
    if (it != row.fields.end() && !Trim(it->second).empty()) return;
  }
  source->columns.erase("time_s");
  for (RawRow& row : source->rows) row.fields.erase("time_s");
}

// Radians read as degrees put every frame within 3 degrees of north: never
// silently. Headings that never leave +-pi (some not 0) look like radians;
// beyond +-2 pi they cannot be.
void WarnAboutAngleUnit(const std::vector<Parsed>& parsed, const NavReadOptions& options, const Source& source,
                        const std::string& path, std::vector<std::string>* warnings) {
  double largest = 0;
  int count = 0;
  for (const Parsed& p : parsed)
    if (p.heading_as_written) {
      largest = std::max(largest, std::fabs(*p.heading_as_written));
      ++count;
    }
  if (count == 0 || largest == 0) return;
  const std::string where = Where(path, source.header_line);
  if (!options.angle_unit && largest <= M_PI + 1e-9)
    warnings->push_back(where + ": headings never leave +-pi (largest " + FormatNumber(largest) + " over " +
                        std::to_string(count) +
                        " lines): radians? They are read as degrees; if they are radians, set \"angle_unit\": "
                        "\"radians\" in the config's navigation object (--config), if degrees, \"angle_unit\": "
                        "\"degrees\" silences this");
  if (options.angle_unit == AngleUnit::kRadians && largest > 2 * M_PI + 1e-9)
    warnings->push_back(where + ": headings reach " + FormatNumber(largest) +
                        ", beyond +-2 pi: degrees? They are read as radians (navigation.angle_unit is \"radians\")");
}

void WarnIfTimeGoesBack(NavTable& table) {
  int backwards = 0;
  std::string first;
  for (size_t i = 1; i < table.records.size(); ++i) {
    const auto& prev = table.records[i - 1].time_s;
    const auto& cur = table.records[i].time_s;
    if (!prev || !cur || *cur >= *prev) continue;
    if (backwards++ == 0)
      first = Where(table.source, table.records[i].line) + ": time goes backwards (" + FormatNumber(*cur) +
              " s after " + FormatNumber(*prev) + " s at line " + std::to_string(table.records[i - 1].line) + ")";
  }
  if (backwards > 0)
    table.warnings.push_back(first + (backwards > 1 ? " and " + std::to_string(backwards - 1) + " more times" : "") +
                             "; frames are ordered by time");
}

}  // namespace

NavTable ReadNavigation(const std::string& path, const NavReadOptions& options) {
  const std::vector<TextLine> lines = ReadTextLines(path);
  NavTable table;
  table.source = path;
  Source source = IsSeedText(lines.front().text) ? ReadSeedText(path, lines, &table.warnings)
                                                 : ReadCsv(path, lines, options, &table.warnings);
  DropEmptyTimeColumn(&source);
  const PositionKind kind = ChoosePosition(source, path, options, &table.warnings);
  table.rejected = std::move(source.rejected);

  std::vector<Parsed> parsed;
  for (const RawRow& row : source.rows) {
    try {
      parsed.push_back(ParseRow(row, kind, options, source.decimal_comma));
    } catch (const Reject& reject) {
      table.rejected.push_back({path, row.line, reject.field, reject.reason});
    }
  }
  WarnAboutAngleUnit(parsed, options, source, path, &table.warnings);
  if (!parsed.empty()) {
    table.origin = options.origin ? *options.origin : parsed.front().geo.value_or(LatLon{});
    std::optional<LocalFrame> frame;
    if (kind != PositionKind::kLocal) frame.emplace(table.origin);
    for (Parsed& p : parsed) {
      if (p.geo) {
        // Far from the origin the local frame is no longer metres.
        const LocalXY xy = frame->FromLatLon(*p.geo);
        const double distance = std::hypot(xy.east, xy.north);
        if (!(distance <= nav_limits::kMaxLocalM)) {
          table.rejected.push_back({path, p.record.line, kind == PositionKind::kUtm ? "easting/northing" : "lat/lon",
                                    "position is " + FormatNumber(std::round(distance / 1000)) +
                                        " km from the origin " + FormatNumber(table.origin.lat) + "," +
                                        FormatNumber(table.origin.lon) + " (limit " +
                                        FormatNumber(nav_limits::kMaxLocalM / 1000) + " km)"});
          continue;
        }
        p.record.pose.east_m = xy.east;
        p.record.pose.north_m = xy.north;
      }
      table.has_images = table.has_images || !p.record.image.empty();
      table.records.push_back(std::move(p.record));
    }
  }
  // Rejections from every pass, back in file order.
  std::stable_sort(table.rejected.begin(), table.rejected.end(),
                   [](const Rejection& a, const Rejection& b) { return a.line < b.line; });
  if (table.records.empty()) {
    if (table.rejected.empty())
      throw InputError(path, source.header_line, "", "no navigation records after the header");
    const Rejection& first = table.rejected.front();
    throw InputError(path, first.line, first.field,
                     "no valid navigation record (" + std::to_string(table.rejected.size()) +
                         (table.rejected.size() == 1 ? " line" : " lines") +
                         " rejected); first problem: " + first.reason);
  }
  table.has_times = source.columns.count("time_s") > 0;
  WarnIfTimeGoesBack(table);
  return table;
}

}  // namespace seamap
