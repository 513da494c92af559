#pragma once
// Navigation as read from a file: one record per line, positions already
// converted to the mission's local frame.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/camera/vehicle_pose.h"
#include "core/geo/lat_lon.h"

namespace seamap {

struct NavRecord {
  std::string image;             // file name relative to the images folder; may be empty
  std::optional<double> time_s;  // seconds, any epoch
  VehiclePose pose;
  int line = 0;  // 1-based line in the source file
};

// A line (or frame) that was skipped, with the reason shown to the user.
struct Rejection {
  std::string file;
  int line = 0;        // 0 when not tied to a line
  std::string field;   // may be empty
  std::string reason;  // e.g. "altitude_m must be > 0, got -1.2"
  std::string Message() const;
};

// How the log writes heading, pitch and roll.
enum class AngleUnit { kDegrees, kRadians };

struct NavReadOptions {
  // Required when positions are local x_m/y_m; otherwise defaults to the
  // first record's position.
  std::optional<LatLon> origin;
  // Extra column names: canonical name -> name used in the file, e.g.
  // {"altitude_m": "alt"}. Canonical names: image, time_s, x_m, y_m, lat, lon,
  // easting, northing, utm_zone, altitude_m, depth_m, heading_deg, pitch_deg, roll_deg.
  std::map<std::string, std::string> columns;
  // UTM zone (1..60) and hemisphere when the file has easting/northing but no zone column.
  std::optional<int> utm_zone;
  bool utm_north = true;
  // False for position logs that have no altitude (a GPS buoy's fixes): the
  // column is then optional and not checked.
  bool require_altitude = true;
  // Unset: degrees, with a warning when the headings look like radians
  // (never beyond +-pi); set: as stated (the config's navigation.angle_unit).
  std::optional<AngleUnit> angle_unit;
  // A time split over several columns (core/nav/split_time.h): part -> name
  // used in the file; parts year, month, day, hour, minute, second, or date
  // and time (of day). Composed into time_s; empty: none.
  std::map<std::string, std::string> time_columns;
  // Throws InputError(source, 0, "navigation.<key>", ...) for a time_columns
  // set that names unknown or too few parts, or that a time_s column doubles.
  void Check(const std::string& source) const;
};

struct NavTable {
  std::string source;  // the file it came from
  LatLon origin;       // origin of the local frame the poses are in
  std::vector<NavRecord> records;
  std::vector<Rejection> rejected;  // lines skipped, with reasons
  bool has_images = false;          // an image column with at least one name
  bool has_times = false;           // a time column
  // Things the user should know that did not stop reading, e.g.
  // "nav.csv:1: ignoring unknown columns: foo, bar".
  std::vector<std::string> warnings;
};

}  // namespace seamap
