#pragma once
// What a mission keeps besides tiles: every frame with its pose and footprint
// (an index into the raw photos) and the vehicle track. Where the trajectory
// was corrected (refined or filtered), the pose a frame was placed with is the
// corrected one and the navigation's original pose is kept beside it.
#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "core/geo/lat_lon.h"

namespace seamap {

// The navigation's pose of a frame placed with a corrected one.
struct NavigatedPose {
  LatLon position;  // vehicle
  double altitude_m = 0, depth_m = 0, heading_deg = 0, pitch_deg = 0, roll_deg = 0;
};

// The navigation's position of a track point placed at a corrected one.
struct NavigatedPosition {
  LatLon position;
  double heading_deg = 0;
};

struct FrameRecord {
  int id = 0;              // frame index
  std::string image;       // file name as in the navigation
  std::string image_path;  // path used to read it
  std::optional<double> time_s;
  LatLon position;  // vehicle
  double altitude_m = 0, depth_m = 0, heading_deg = 0, pitch_deg = 0, roll_deg = 0;
  std::array<LatLon, 4> footprint{};  // image corners on the seabed (TL, TR, BR, BL)
  std::string status;                 // "used" or the rejection reason
  std::optional<NavigatedPose> nav;   // set when the frame was placed with a corrected pose
};

struct TrackPoint {
  int seq = 0;
  std::optional<double> time_s;
  LatLon position;
  double altitude_m = 0, depth_m = 0, heading_deg = 0;
  std::optional<NavigatedPosition> nav;  // set when the point is a corrected position
};

// An object on the seabed: found by a recogniser or marked by an operator.
struct Detection {
  int64_t id = 0;
  std::string class_name;
  double score = 1;
  LatLon position;
  std::string note;
  std::string source = "operator";  // "operator" or the recogniser's name
  std::optional<int> frame_id;      // the photo it was found in
  std::optional<double> time_s;
  std::string created, updated;  // ISO 8601 UTC
  int64_t seq = 0;               // change number: grows with every change
};

}  // namespace seamap
