#include "core/detect/detection_record.h"

#include <algorithm>
#include <cmath>

namespace seamap {
namespace {

// Point in a convex or concave quad (even-odd rule), in lon/lat scaled by cos(lat).
bool Inside(const std::array<LatLon, 4>& q, LatLon p) {
  bool in = false;
  for (int i = 0, j = 3; i < 4; j = i++) {
    const LatLon a = q[i], b = q[j];
    if ((a.lat > p.lat) != (b.lat > p.lat) && p.lon < (b.lon - a.lon) * (p.lat - a.lat) / (b.lat - a.lat) + a.lon)
      in = !in;
  }
  return in;
}

}  // namespace

void AttachFrames(std::vector<RecognisedObject>& objects, const std::vector<FrameRecord>& frames, size_t max_frames) {
  for (RecognisedObject& o : objects) {
    const double k = std::cos(o.centre.lat * M_PI / 180);
    std::vector<std::pair<double, const FrameRecord*>> seen;
    for (const FrameRecord& f : frames) {
      if (f.status != "used" || !Inside(f.footprint, o.centre)) continue;
      double lat = 0, lon = 0;
      for (const LatLon& c : f.footprint) lat += c.lat / 4, lon += c.lon / 4;
      const double d = std::hypot(lat - o.centre.lat, (lon - o.centre.lon) * k);
      seen.push_back({d, &f});
    }
    std::stable_sort(seen.begin(), seen.end(), [](const auto& a, const auto& b) {
      return a.first != b.first ? a.first < b.first : a.second->id < b.second->id;
    });
    o.frames.clear();
    for (size_t i = 0; i < seen.size() && i < max_frames; ++i) o.frames.push_back(seen[i].second->id);
    o.time_s = seen.empty() ? std::nullopt : seen[0].second->time_s;
  }
}

Detection ToDetection(const RecognisedObject& o) {
  Detection d;
  d.class_name = o.class_name;
  d.score = o.score;
  d.position = o.centre;
  d.source = "recogniser";
  if (!o.frames.empty()) d.frame_id = o.frames[0];
  d.time_s = o.time_s;
  return d;
}

}  // namespace seamap
