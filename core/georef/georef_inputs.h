#pragma once
// The georeferencing's position logs, read through the navigation reader
// (core/nav: column aliases, separators, time formats, bad rows skipped and
// listed): the buoy's GPS fixes and the vehicle's depth over time.
#include <string>
#include <utility>
#include <vector>

#include "core/geo/lat_lon.h"
#include "core/geo/local_frame.h"
#include "core/georef/buoy_track.h"
#include "core/nav/nav_table.h"

namespace seamap {

struct BuoyFixRecord {
  double time_s = 0;
  LatLon position;
  double sigma_m = 0;  // 0 = not given
  double hdop = 0;     // 0 = not given
  int line = 0;
};

struct BuoyLog {
  std::vector<BuoyFixRecord> fixes;
  std::vector<Rejection> rejected;  // rows skipped, with reasons (fix_quality 0 among them)
  std::vector<std::string> warnings;
};

// CSV with time_s and lat,lon (or easting,northing with a zone); optional
// sigma_m (horizontal sigma per axis), hdop, fix_quality (NMEA: 0 = no fix,
// dropped). Throws InputError naming file, line and field when no fix is
// usable or the file has no time column.
BuoyLog ReadBuoyLog(const std::string& path);

// The median latitude and longitude of the fixes: the working frame's centre.
LatLon MedianPosition(const BuoyLog& log);

// The fixes in the working frame (metres east, north of its origin).
BuoyTrack MakeBuoyTrack(const BuoyLog& log, const LocalFrame& frame);

struct DepthLog {
  std::vector<std::pair<double, double>> samples;  // time_s, depth_m (or altitude_m)
  std::vector<Rejection> rejected;
  std::vector<std::string> warnings;
};

// CSV with time_s and depth_m (aliases apply). Throws InputError naming file,
// line and field when a column is missing or no row is usable.
DepthLog ReadDepthLog(const std::string& path);

// CSV with time_s and altitude_m (a sounder's or DVL's height above the
// seabed, > 0), read the same way.
DepthLog ReadAltitudeLog(const std::string& path);

}  // namespace seamap
