#pragma once
// What the recogniser reports for one object on the seabed, after merging
// the boxes of every window and level that saw it.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "core/geo/lat_lon.h"
#include "core/geo/local_frame.h"

namespace seamap {

struct RecognisedObject {
  std::string class_name;
  int class_id = 0;
  float score = 0;
  int zoom = 0;                 // level of the representative box
  std::vector<int> levels;      // every zoom that saw it, finest first
  std::array<LatLon, 5> box{};  // NW, SW, SE, NE, NW
  LatLon centre;
  LocalXY position_m;              // east/north from the mission origin
  std::array<double, 2> size_m{};  // east-west, north-south
  bool truncated = false;          // only cut boxes were seen
  std::string alt_class;           // another class that claimed the same box ("" = none)
  std::string model;               // file name#content hash
  std::vector<int> frames;         // frames whose footprint holds the centre, nearest first (<= 10)
  std::optional<double> time_s;    // time of frames[0]
};

}  // namespace seamap
