#include "server/detection_registry.h"

#include <cmath>
#include <ctime>
#include <sstream>

#include "core/tiles/record_json.h"
#include "server/api_error.h"

namespace seamap::server {
namespace {

constexpr size_t kMaxClassLength = 64;
constexpr size_t kMaxNoteLength = 4000;

std::string UtcNow() {
  std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

double ParseNumber(const std::string& text, const std::string& name) {
  try {
    size_t used = 0;
    double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw ApiError(400, "parameter '" + name + "': expected a number, got '" + text + "'");
}

// The "type" member, or "" when missing or not a string (value() would throw
// nlohmann's type_error, answered 500 instead of 400).
std::string TypeOf(const nlohmann::json& j) {
  auto it = j.find("type");
  return it != j.end() && it->is_string() ? it->get<std::string>() : "";
}

// Geometry of a Feature: a Point [lon, lat] (an altitude is allowed and ignored).
LatLon ParsePoint(const nlohmann::json& geometry) {
  if (!geometry.is_object() || TypeOf(geometry) != "Point") throw ApiError(400, "geometry: expected a GeoJSON Point");
  const auto& c = geometry.contains("coordinates") ? geometry["coordinates"] : nlohmann::json();
  if (!c.is_array() || c.size() < 2 || c.size() > 3 || !c[0].is_number() || !c[1].is_number())
    throw ApiError(400, "geometry.coordinates: expected [lon, lat]");
  const double lon = c[0].get<double>(), lat = c[1].get<double>();
  if (!(lon >= -180 && lon <= 180) || !(lat >= -90 && lat <= 90))
    throw ApiError(400, "geometry.coordinates: lon must be in [-180, 180] and lat in [-90, 90]");
  return {lat, lon};
}

// Applies the writable properties; read-only ones a client echoes back are ignored.
void ApplyProperties(const nlohmann::json& props, Detection* d) {
  if (!props.is_object()) throw ApiError(400, "properties: expected an object");
  static const std::set<std::string> kReadOnly = {"id", "source", "created", "updated", "seq", "frame_id"};
  for (const auto& [key, value] : props.items()) {
    if (key == "class") {
      if (!value.is_string() || value.get<std::string>().empty() || value.get<std::string>().size() > kMaxClassLength)
        throw ApiError(400, "properties.class: expected a non-empty string of at most 64 characters");
      d->class_name = value.get<std::string>();
    } else if (key == "note") {
      if (!value.is_string() || value.get<std::string>().size() > kMaxNoteLength)
        throw ApiError(400, "properties.note: expected a string of at most 4000 characters");
      d->note = value.get<std::string>();
    } else if (key == "score") {
      if (!value.is_number() || value.get<double>() < 0 || value.get<double>() > 1)
        throw ApiError(400, "properties.score: expected a number in [0, 1]");
      d->score = value.get<double>();
    } else if (key == "time_s") {
      if (value.is_null())
        d->time_s.reset();
      else if (value.is_number())
        d->time_s = value.get<double>();
      else
        throw ApiError(400, "properties.time_s: expected a number of seconds or null");
    } else if (!kReadOnly.count(key)) {
      throw ApiError(400, "properties." + key + ": unknown property; expected class, note, score or time_s");
    }
  }
}

}  // namespace

DetectionFilter ParseDetectionFilter(const std::optional<std::string>& bbox, const std::optional<std::string>& classes,
                                     const std::optional<std::string>& min_score,
                                     const std::optional<std::string>& since) {
  DetectionFilter f;
  if (bbox) {
    std::vector<double> v;
    std::stringstream in(*bbox);
    std::string part;
    while (std::getline(in, part, ',')) v.push_back(ParseNumber(part, "bbox"));
    if (v.size() != 4 || v[0] > v[2] || v[1] > v[3])
      throw ApiError(400, "parameter 'bbox': expected west,south,east,north with west <= east and south <= north");
    f.bbox = LatLonBounds{v[0], v[1], v[2], v[3]};
  }
  if (classes) {
    std::stringstream in(*classes);
    std::string part;
    while (std::getline(in, part, ','))
      if (!part.empty()) f.classes.insert(part);
  }
  if (min_score) f.min_score = ParseNumber(*min_score, "min_score");
  if (since) {
    const double v = ParseNumber(*since, "since");
    if (v < 0 || v != std::floor(v)) throw ApiError(400, "parameter 'since': expected a change number >= 0");
    f.since = static_cast<int64_t>(v);
  }
  return f;
}

nlohmann::json DetectionFeature(const Detection& d) {
  // Every stored field but lat/lon, which the Point geometry carries.
  nlohmann::json props = DetectionToJson(d);
  props.erase("lat");
  props.erase("lon");
  return {{"type", "Feature"},
          {"id", d.id},
          {"geometry", {{"type", "Point"}, {"coordinates", {d.position.lon, d.position.lat}}}},
          {"properties", std::move(props)}};
}

void DetectionRegistry::Load(const TileStore& store) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Detection& d : store.Detections()) {
    detections_[d.id] = d;
    last_seq_ = std::max(last_seq_, d.seq);
    last_id_ = std::max(last_id_, d.id);
  }
}

nlohmann::json DetectionRegistry::Query(const DetectionFilter& f) const {
  nlohmann::json features = nlohmann::json::array();
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, d] : detections_) {
    if (f.bbox && (d.position.lon < f.bbox->west || d.position.lon > f.bbox->east || d.position.lat < f.bbox->south ||
                   d.position.lat > f.bbox->north))
      continue;
    if (!f.classes.empty() && !f.classes.count(d.class_name)) continue;
    if (f.min_score && d.score < *f.min_score) continue;
    if (f.since && d.seq <= *f.since) continue;
    features.push_back(DetectionFeature(d));
  }
  return {{"type", "FeatureCollection"}, {"features", std::move(features)}, {"last_seq", last_seq_}};
}

std::optional<nlohmann::json> DetectionRegistry::Get(int64_t id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = detections_.find(id);
  if (it == detections_.end()) return std::nullopt;
  return DetectionFeature(it->second);
}

void DetectionRegistry::CheckWritable() const {
  if (!store_) throw ApiError(403, "this mission is open read-only; detections cannot be changed");
}

void DetectionRegistry::Announce(const char* action, const Detection& d) {
  if (!events_) return;
  nlohmann::json data = {{"action", action}, {"id", d.id}};
  data["feature"] = std::string(action) == "deleted" ? nlohmann::json(nullptr) : DetectionFeature(d);
  events_->Publish("detection", data.dump());
}

nlohmann::json DetectionRegistry::Create(const nlohmann::json& feature) {
  CheckWritable();
  if (!feature.is_object() || TypeOf(feature) != "Feature")
    throw ApiError(400, "body: expected a GeoJSON Feature with a Point geometry");
  Detection d;
  d.position = ParsePoint(feature.contains("geometry") ? feature["geometry"] : nlohmann::json());
  ApplyProperties(feature.contains("properties") ? feature["properties"] : nlohmann::json::object(), &d);
  if (d.class_name.empty()) throw ApiError(400, "properties.class: required (what the object is)");
  d.source = "operator";
  d.created = d.updated = UtcNow();
  std::lock_guard<std::mutex> lock(mutex_);
  d.id = ++last_id_;  // never reuses the id of a mark deleted in this session
  d.seq = ++last_seq_;
  store_->PutDetection(d);
  store_->Flush();
  detections_[d.id] = d;
  Announce("created", d);
  return DetectionFeature(d);
}

std::map<int64_t, Detection>::iterator DetectionRegistry::OperatorMark(int64_t id, const char* verb) {
  auto it = detections_.find(id);
  if (it == detections_.end()) throw ApiError(404, "no detection " + std::to_string(id));
  if (it->second.source != "operator")
    throw ApiError(403, "detection " + std::to_string(id) + " comes from '" + it->second.source +
                            "'; only operator marks can be " + verb);
  return it;
}

nlohmann::json DetectionRegistry::Update(int64_t id, const nlohmann::json& patch) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = OperatorMark(id, "changed");
  if (!patch.is_object()) throw ApiError(400, "body: expected a GeoJSON Feature or a properties object");
  Detection d = it->second;
  if (TypeOf(patch) == "Feature") {
    if (patch.contains("geometry") && !patch["geometry"].is_null()) d.position = ParsePoint(patch["geometry"]);
    if (patch.contains("properties") && !patch["properties"].is_null()) ApplyProperties(patch["properties"], &d);
  } else {
    ApplyProperties(patch, &d);
  }
  d.updated = UtcNow();
  d.seq = ++last_seq_;
  store_->PutDetection(d);
  store_->Flush();
  it->second = d;
  Announce("updated", d);
  return DetectionFeature(d);
}

void DetectionRegistry::Delete(int64_t id) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = OperatorMark(id, "deleted");
  const Detection d = it->second;
  store_->DeleteDetection(id);
  store_->Flush();
  detections_.erase(it);
  ++last_seq_;
  Announce("deleted", d);
}

}  // namespace seamap::server
