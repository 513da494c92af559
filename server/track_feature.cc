#include "server/track_feature.h"

#include "server/api_error.h"

namespace seamap::server {

TrackSource ParseTrackSource(const std::optional<std::string>& text) {
  if (!text || *text == "estimated") return TrackSource::kEstimated;
  if (*text == "nav") return TrackSource::kNav;
  if (*text == "buoy") return TrackSource::kBuoy;
  if (*text == "refined") return TrackSource::kRefined;
  throw ApiError(
      400, "parameter 'source': expected 'estimated', 'refined', 'nav' or 'buoy', got '" + text->substr(0, 100) + "'");
}

const char* TrackSourceName(TrackSource source) {
  switch (source) {
    case TrackSource::kNav:
      return "nav";
    case TrackSource::kBuoy:
      return "buoy";
    case TrackSource::kRefined:
      return "refined";
    case TrackSource::kEstimated:
      break;
  }
  return "estimated";
}

LatLon TrackPosition(const TrackPoint& point, TrackSource source) {
  return source == TrackSource::kNav && point.nav ? point.nav->position : point.position;
}

nlohmann::json TrackFeature(const std::vector<TrackPoint>& points, TrackSource source, int next, bool corrected) {
  nlohmann::json coords = nlohmann::json::array(), times = nlohmann::json::array();
  for (const auto& p : points) {
    const LatLon at = TrackPosition(p, source);
    coords.push_back({at.lon, at.lat});
    times.push_back(p.time_s ? nlohmann::json(*p.time_s) : nlohmann::json(nullptr));
  }
  nlohmann::json geometry = nullptr;
  if (coords.size() >= 2) geometry = {{"type", "LineString"}, {"coordinates", coords}};
  return {{"type", "Feature"},
          {"geometry", geometry},
          {"properties",
           {{"source", TrackSourceName(source)},
            {"corrected", corrected},
            {"from", points.empty() ? next : points.front().seq},
            {"next", next},
            {"times", times},
            {"coordinates", coords.size() < 2 ? coords : nlohmann::json(nullptr)}}}};
}

}  // namespace seamap::server
