#include "core/detect/detection_record.h"

#include <algorithm>
#include <cmath>

#include "core/mission/detection_book.h"

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
  d.model = o.model;
  d.level = o.zoom;
  d.levels = o.levels;
  d.box.assign(o.box.begin(), o.box.end());
  d.position_m = std::array<double, 2>{o.position_m.east, o.position_m.north};
  d.size_m = o.size_m;
  d.frames = o.frames;
  if (!o.frames.empty()) d.frame_id = o.frames[0];
  d.time_s = o.time_s;
  d.status = "unconfirmed";
  d.truncated = o.truncated;
  d.alt_class = o.alt_class;
  return d;
}

}  // namespace seamap

namespace seamap {

std::vector<Detection> StoreRecognised(TileStore& store, const std::vector<RecognisedObject>& objects,
                                       const std::string& model, const std::vector<std::string>& class_names) {
  std::vector<Detection> found;
  for (const RecognisedObject& o : objects) found.push_back(ToDetection(o));
  return PublishFound(store, std::move(found), model, class_names);
}

nlohmann::json RecognisedFeatureCollection(const std::vector<RecognisedObject>& objects) {
  nlohmann::json features = nlohmann::json::array();
  for (const RecognisedObject& o : objects) {
    nlohmann::json ring = nlohmann::json::array();
    for (const LatLon& p : o.box) ring.push_back({p.lon, p.lat});
    nlohmann::json props = {{"class", o.class_name},
                            {"class_id", o.class_id},
                            {"score", o.score},
                            {"source", "recogniser"},
                            {"model", o.model},
                            {"level", o.zoom},
                            {"levels", o.levels},
                            {"box", {ring}},
                            {"position_m", {o.position_m.east, o.position_m.north}},
                            {"size_m", {o.size_m[0], o.size_m[1]}},
                            {"truncated", o.truncated},
                            {"alt_class", o.alt_class.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.alt_class)},
                            {"frames", o.frames},
                            {"frame_id", o.frames.empty() ? nlohmann::json(nullptr) : nlohmann::json(o.frames[0])},
                            {"time_s", o.time_s ? nlohmann::json(*o.time_s) : nlohmann::json(nullptr)}};
    features.push_back({{"type", "Feature"},
                        {"geometry", {{"type", "Point"}, {"coordinates", {o.centre.lon, o.centre.lat}}}},
                        {"properties", props}});
  }
  return {{"type", "FeatureCollection"}, {"features", features}};
}

}  // namespace seamap
