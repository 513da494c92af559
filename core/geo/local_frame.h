#pragma once
// The mission's local metric frame: east/north metres from an origin on the
// WGS84 ellipsoid, realised as a transverse Mercator projection centred on the
// origin (through PROJ). Scale error is below 1e-8 within a few km of the
// origin, unlike a spherical shortcut (about 0.2 % at mid latitudes).
#include <memory>
#include <mutex>

#include "core/geo/lat_lon.h"

namespace seamap {

struct LocalXY {
  double east = 0;   // metres
  double north = 0;  // metres
};

class LocalFrame {
 public:
  // Throws InputError("--origin", ...) when the origin is out of range.
  explicit LocalFrame(LatLon origin);
  ~LocalFrame();
  LocalFrame(const LocalFrame& other);
  LocalFrame& operator=(const LocalFrame& other);

  const LatLon& origin() const { return origin_; }
  LatLon ToLatLon(LocalXY xy) const;
  LocalXY FromLatLon(LatLon ll) const;

 private:
  struct Proj;
  LatLon origin_;
  std::unique_ptr<Proj> proj_;  // guarded by mutex_: PROJ objects are not thread-safe
  mutable std::mutex mutex_;
};

// UTM (WGS84) to geographic. zone 1..60; north=false for the southern hemisphere.
// Throws InputError naming the zone when it is out of range.
LatLon UtmToLatLon(double easting, double northing, int zone, bool north);

}  // namespace seamap
