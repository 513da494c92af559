#pragma once
// UTM (WGS84) through PROJ: the zone a position falls in (with the Norway and
// Svalbard exceptions) and conversions both ways. A survey keeps one zone even
// where it crosses a zone boundary: UTM is valid a few hundred km beyond it.
#include <memory>
#include <string>

#include "core/geo/lat_lon.h"

namespace seamap {

struct UtmZoneId {
  int zone = 0;       // 1..60
  bool north = true;  // hemisphere
  int Epsg() const { return (north ? 32600 : 32700) + zone; }
  std::string Name() const { return std::to_string(zone) + (north ? "N" : "S"); }  // "32N"
};

struct UtmXY {
  double easting = 0;   // metres, false easting 500 km
  double northing = 0;  // metres, false northing 10,000 km in the south
};

// floor((lon + 180) / 6) + 1, except 32V (Norway's west coast) and 31X..37X
// (Svalbard); hemisphere from the sign of the latitude.
UtmZoneId UtmZoneFor(LatLon position);

// One zone's projection, kept open for many points. Not thread-safe.
class UtmProjection {
 public:
  // Throws InputError naming "utm_zone" when the zone is out of range.
  explicit UtmProjection(UtmZoneId zone);
  ~UtmProjection();
  UtmProjection(const UtmProjection&) = delete;
  UtmProjection& operator=(const UtmProjection&) = delete;

  const UtmZoneId& zone() const { return zone_; }
  UtmXY Forward(LatLon position) const;
  LatLon Inverse(UtmXY xy) const;

 private:
  struct Proj;
  UtmZoneId zone_;
  std::unique_ptr<Proj> proj_;
};

}  // namespace seamap
