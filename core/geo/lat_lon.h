#pragma once
// A WGS84 geographic position in degrees.
namespace seamap {

struct LatLon {
  double lat = 0;  // degrees, north positive, [-90, 90]
  double lon = 0;  // degrees, east positive, [-180, 180]
};

}  // namespace seamap
