#pragma once
// Which detections a reader asks for (the REST API's query parameters,
// `seamap detections-pack`'s options).
#include <cstdint>
#include <optional>
#include <set>
#include <string>

#include "core/geo/web_mercator.h"
#include "core/tiles/mission_records.h"

namespace seamap {

struct DetectionFilter {
  std::optional<LatLonBounds> bbox;
  std::set<std::string> classes;  // empty: all
  std::optional<double> min_score;
  std::optional<int64_t> since;    // changed after this seq
  std::set<std::string> statuses;  // empty: all ("unconfirmed", "confirmed", "rejected")
  std::set<std::string> sources;   // empty: all ("recogniser", "operator", "stereo")
};

// Parses the filter's texts (bbox=w,s,e,n, class=a,b, min_score, since,
// status=a,b, source=a,b). Throws DetectionError(kInvalid) whose field is the
// parameter's name (bbox, class, min_score, since, status, source).
DetectionFilter ParseDetectionFilter(const std::optional<std::string>& bbox, const std::optional<std::string>& classes,
                                     const std::optional<std::string>& min_score,
                                     const std::optional<std::string>& since,
                                     const std::optional<std::string>& status = std::nullopt,
                                     const std::optional<std::string>& source = std::nullopt);

bool Passes(const DetectionFilter& filter, const Detection& d);

}  // namespace seamap
