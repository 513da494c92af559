#pragma once
// report.json of `seamap georef`: the transform of the first sub-map at the
// top with counts and residuals over every sub-map, then each sub-map's own.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geo/lat_lon.h"
#include "core/geo/utm.h"
#include "core/georef/georeferencer.h"

namespace seamap {

struct GeorefReportContext {
  LatLon origin;  // of the working frame
  UtmZoneId utm_zone;
  std::string buoy_file;
  int buoy_fixes = 0;
  int buoy_rows_rejected = 0;
  std::vector<std::string> warnings;
};

nlohmann::json SubmapReport(const SubmapGeoref& submap);
nlohmann::json GeorefReport(const std::vector<SubmapGeoref>& submaps, const GeorefReportContext& context);

}  // namespace seamap
