#pragma once
// A simulated survey's truth as an operator's review (issue 32, for training
// and its tests): the recogniser's detections that match a truth object of
// the same class are confirmed, the others rejected, and every truth object
// no detection matched becomes an operator's mark with its box, as an
// operator who checked every object on a dive would leave the mission.
#include <string>
#include <vector>

#include "core/geo/lat_lon.h"
#include "core/mission/detection_book.h"

namespace seamap {

struct TruthObject {
  std::string class_name;
  LatLon centre;                                    // of the footprint's east/north box
  double west = 0, south = 0, east = 0, north = 0;  // its bounds, degrees
  double size_m = 0;                                // the box's longer side
};

// truth/objects.json of `seamap simulate --objects` (InputError naming the file and key).
std::vector<TruthObject> ReadObjectsTruth(const std::string& path);

struct TruthReviewOptions {
  // A detection matches a truth object whose centre lies within
  // max(min_radius_m, radius_fraction x its size) (nearest pairs first, one to one).
  double min_radius_m = 0.10, radius_fraction = 0.25;
  std::string note = "review --truth";
};

struct TruthReviewResult {
  int confirmed = 0, rejected = 0, added = 0;  // added: operator marks with a box for missed objects
  int kept = 0;                                // already reviewed detections left as they were
};

// Reviews the recogniser's unreviewed detections in `book` and adds the
// missed objects. Detections already confirmed or rejected keep their status.
TruthReviewResult ReviewAgainstTruth(DetectionBook& book, const std::vector<TruthObject>& truth,
                                     const TruthReviewOptions& options = {});

}  // namespace seamap
