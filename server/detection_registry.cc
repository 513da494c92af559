#include "server/detection_registry.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/tiles/detection_match.h"
#include "core/tiles/mission_classes.h"
#include "core/tiles/modem_record.h"
#include "core/tiles/record_json.h"
#include "core/util/utc_time.h"
#include "server/api_error.h"

namespace seamap::server {
namespace {

constexpr size_t kMaxClassLength = 64;
constexpr size_t kMaxNoteLength = 4000;

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
  static const std::set<std::string> kReadOnly = {
      "id",  "source",     "created", "updated", "seq",       "frame_id",  "model",       "level",  "levels",
      "box", "position_m", "size_m",  "frames",  "truncated", "alt_class", "heading_deg", "depth_m"};
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
    } else if (key == "status") {
      if (!value.is_string() || !IsDetectionStatus(value.get<std::string>()))
        throw ApiError(400, "properties.status: expected \"unconfirmed\", \"confirmed\" or \"rejected\"");
      d->status = value.get<std::string>();
    } else if (key == "time_s") {
      if (value.is_null())
        d->time_s.reset();
      else if (value.is_number())
        d->time_s = value.get<double>();
      else
        throw ApiError(400, "properties.time_s: expected a number of seconds or null");
    } else if (!kReadOnly.count(key)) {
      throw ApiError(400, "properties." + key + ": unknown property; expected class, note, score, status or time_s");
    }
  }
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ','))
    if (!part.empty()) out.push_back(part);
  return out;
}

bool Passes(const DetectionFilter& f, const Detection& d) {
  if (f.bbox && (d.position.lon < f.bbox->west || d.position.lon > f.bbox->east || d.position.lat < f.bbox->south ||
                 d.position.lat > f.bbox->north))
    return false;
  if (!f.classes.empty() && !f.classes.count(d.class_name)) return false;
  if (f.min_score && d.score < *f.min_score) return false;
  if (f.since && d.seq <= *f.since) return false;
  if (!f.statuses.empty() && !f.statuses.count(d.status)) return false;
  if (!f.sources.empty() && !f.sources.count(d.source)) return false;
  return true;
}

// A recogniser's detection allows `status` and `note` to change; any other
// property may be echoed back unchanged, but not changed.
void CheckRecogniserPatch(const Detection& d, const nlohmann::json& patch) {
  const std::string who = "detection " + std::to_string(d.id) + " comes from the " + d.source;
  auto refuse = [&](const std::string& what) {
    throw ApiError(403, who + "; only its status and note can be changed, not " + what);
  };
  const bool feature = TypeOf(patch) == "Feature";
  if (feature && patch.contains("geometry") && !patch["geometry"].is_null()) {
    const LatLon p = ParsePoint(patch["geometry"]);
    if (p.lat != d.position.lat || p.lon != d.position.lon) refuse("its position");
  }
  const nlohmann::json& props =
      feature ? (patch.contains("properties") ? patch["properties"] : nlohmann::json()) : patch;
  if (props.is_null()) return;
  if (!props.is_object()) throw ApiError(400, "properties: expected an object");
  const nlohmann::json current = DetectionToJson(d);
  for (const auto& [key, value] : props.items()) {
    if (key == "status" || key == "note") continue;
    auto it = current.find(key);
    if (it == current.end() || *it != value) refuse("'" + key + "'");
  }
}

}  // namespace

DetectionFilter ParseDetectionFilter(const std::optional<std::string>& bbox, const std::optional<std::string>& classes,
                                     const std::optional<std::string>& min_score,
                                     const std::optional<std::string>& since, const std::optional<std::string>& status,
                                     const std::optional<std::string>& source) {
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
  if (classes)
    for (const std::string& v : SplitList(*classes)) f.classes.insert(v);
  if (min_score) f.min_score = ParseNumber(*min_score, "min_score");
  if (since) {
    const double v = ParseNumber(*since, "since");
    if (v < 0 || v != std::floor(v)) throw ApiError(400, "parameter 'since': expected a change number >= 0");
    f.since = static_cast<int64_t>(v);
  }
  if (status)
    for (const std::string& v : SplitList(*status)) {
      if (!IsDetectionStatus(v))
        throw ApiError(400, "parameter 'status': '" + v + "' is not unconfirmed, confirmed or rejected");
      f.statuses.insert(v);
    }
  if (source)
    for (const std::string& v : SplitList(*source)) {
      if (!IsDetectionSource(v))
        throw ApiError(400, "parameter 'source': '" + v + "' is not recogniser, operator or stereo");
      f.sources.insert(v);
    }
  return f;
}

void DetectionRegistry::Load(const TileStore& store) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const Detection& d : store.Detections()) {
    detections_[d.id] = d;
    stored_seq_[d.id] = d.seq;
    last_seq_ = std::max(last_seq_, d.seq);
    last_id_ = std::max(last_id_, d.id);
  }
  classes_ = MissionClassTable(store);
}

void DetectionRegistry::Refresh(const TileStore& store) {
  std::lock_guard<std::mutex> lock(mutex_);
  RefreshLocked(store);
}

void DetectionRegistry::RefreshLocked(const TileStore& store) {
  std::map<int64_t, Detection> in_store;
  for (Detection& d : store.Detections()) in_store[d.id] = std::move(d);
  for (auto& [id, d] : in_store) {
    last_id_ = std::max(last_id_, id);
    auto seen = stored_seq_.find(id);
    if (seen != stored_seq_.end() && seen->second == d.seq) continue;
    stored_seq_[id] = d.seq;
    // The other process numbered it from the file alone; browsers asking
    // `since` our last seq (deletions of this session count) must still get it.
    if (d.seq <= last_seq_) d.seq = ++last_seq_;
    last_seq_ = d.seq;
    const bool known = detections_.count(id) > 0;
    deleted_.erase(id);
    detections_[id] = d;
    Announce(known ? "updated" : "created", d);
  }
  for (auto it = detections_.begin(); it != detections_.end();) {
    if (in_store.count(it->first)) {
      ++it;
      continue;
    }
    Detection gone = it->second;
    stored_seq_.erase(gone.id);
    it = detections_.erase(it);
    gone.seq = ++last_seq_;
    deleted_[gone.id] = gone;
    Announce("deleted", gone);
  }
  const std::vector<std::string> classes = MissionClassTable(store);
  if (classes.size() > classes_.size()) classes_ = classes;
}

nlohmann::json DetectionRegistry::Query(const DetectionFilter& f) const {
  nlohmann::json features = nlohmann::json::array();
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, d] : detections_) {
    if (!Passes(f, d)) continue;
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

void DetectionRegistry::Store(const Detection& d) {
  store_->PutDetection(d);
  stored_seq_[d.id] = d.seq;
  if (ExtendClassTable(&classes_, {d.class_name})) StoreClassTable(store_, classes_);
  if (!t0_stored_) t0_stored_ = StoreMissionT0(store_).has_value();
}

void DetectionRegistry::Forget(std::map<int64_t, Detection>::iterator it) {
  Detection gone = it->second;
  store_->DeleteDetection(gone.id);
  stored_seq_.erase(gone.id);
  detections_.erase(it);
  gone.seq = ++last_seq_;
  deleted_[gone.id] = gone;
  Announce("deleted", gone);
}

nlohmann::json DetectionRegistry::Create(const nlohmann::json& feature) {
  CheckWritable();
  if (!feature.is_object() || TypeOf(feature) != "Feature")
    throw ApiError(400, "body: expected a GeoJSON Feature with a Point geometry");
  Detection d;
  d.position = ParsePoint(feature.contains("geometry") ? feature["geometry"] : nlohmann::json());
  d.status = "confirmed";  // an operator's own mark, unless the body says otherwise
  ApplyProperties(feature.contains("properties") ? feature["properties"] : nlohmann::json::object(), &d);
  if (d.class_name.empty()) throw ApiError(400, "properties.class: required (what the object is)");
  d.source = "operator";
  d.created = d.updated = UtcNowIso8601();
  std::lock_guard<std::mutex> lock(mutex_);
  RefreshLocked(*store_);
  d.id = ++last_id_;  // never reuses the id of a mark deleted in this session
  d.seq = ++last_seq_;
  Store(d);
  store_->Flush();
  detections_[d.id] = d;
  Announce("created", d);
  return DetectionFeature(d);
}

nlohmann::json DetectionRegistry::Update(int64_t id, const nlohmann::json& patch) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  RefreshLocked(*store_);
  auto it = detections_.find(id);
  if (it == detections_.end()) throw ApiError(404, "no detection " + std::to_string(id));
  if (!patch.is_object()) throw ApiError(400, "body: expected a GeoJSON Feature or a properties object");
  Detection d = it->second;
  if (d.source != "operator") CheckRecogniserPatch(d, patch);
  if (TypeOf(patch) == "Feature") {
    if (patch.contains("geometry") && !patch["geometry"].is_null()) d.position = ParsePoint(patch["geometry"]);
    if (patch.contains("properties") && !patch["properties"].is_null()) ApplyProperties(patch["properties"], &d);
  } else {
    ApplyProperties(patch, &d);
  }
  if (d.source != "operator") {  // echoed read-only values are equal; keep the originals exactly
    Detection kept = it->second;
    kept.status = d.status;
    kept.note = d.note;
    d = kept;
  }
  d.updated = UtcNowIso8601();
  d.seq = ++last_seq_;
  Store(d);
  store_->Flush();
  it->second = d;
  Announce("updated", d);
  return DetectionFeature(d);
}

void DetectionRegistry::Delete(int64_t id) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  RefreshLocked(*store_);
  auto it = detections_.find(id);
  if (it == detections_.end()) throw ApiError(404, "no detection " + std::to_string(id));
  if (it->second.source != "operator")
    throw ApiError(403, "detection " + std::to_string(id) + " comes from the " + it->second.source +
                            "; it cannot be deleted, only rejected (PATCH status \"rejected\")");
  Forget(it);
  store_->Flush();
}

PublishResult DetectionRegistry::Publish(std::vector<Detection> batch, const PublishOptions& options) {
  CheckWritable();
  PublishResult result;
  const std::string now = UtcNowIso8601();
  std::lock_guard<std::mutex> lock(mutex_);
  RefreshLocked(*store_);
  if (ExtendClassTable(&classes_, options.model_classes)) StoreClassTable(store_, classes_);
  // Which earlier detection each one continues: by id when it has one (an
  // operator's mark is not ours to change), else the same object nearby.
  std::vector<std::map<int64_t, Detection>::iterator> continues(batch.size(), detections_.end());
  std::set<int64_t> seen;
  std::vector<size_t> by_place;
  for (size_t i = 0; i < batch.size(); ++i) {
    Detection& d = batch[i];
    if (d.source != "stereo") d.source = "recogniser";
    auto it = d.id > 0 ? detections_.find(d.id) : detections_.end();
    if (it != detections_.end() && it->second.source != "operator") {
      continues[i] = it;
      seen.insert(d.id);
    } else if (d.id <= 0) {
      by_place.push_back(i);
    }
  }
  std::vector<Detection> earlier, found;
  for (const auto& [id, e] : detections_)
    if (!seen.count(id)) earlier.push_back(e);
  for (size_t i : by_place) found.push_back(batch[i]);
  const std::vector<int> match = MatchEarlier(earlier, found);
  for (size_t k = 0; k < by_place.size(); ++k)
    if (match[k] >= 0) continues[by_place[k]] = detections_.find(earlier[match[k]].id);
  for (size_t i = 0; i < batch.size(); ++i) {
    Detection& d = batch[i];
    auto it = continues[i];
    if (it != detections_.end()) {
      const Detection& old = it->second;
      d.id = old.id;
      d.status = old.status;  // the operator's call: a rejected one stays rejected
      d.note = old.note;
      d.created = old.created;
      d.updated = old.updated;
      d.seq = old.seq;
      seen.insert(d.id);
      result.ids.push_back(d.id);
      if (DetectionToJson(d) == DetectionToJson(old)) {
        ++result.unchanged;
        continue;
      }
      d.updated = now;
      d.seq = ++last_seq_;
      Store(d);
      it->second = d;
      ++result.updated;
      Announce("updated", d);
    } else {
      if (d.id <= 0 || detections_.count(d.id)) d.id = ++last_id_;  // an operator's id is never taken over
      last_id_ = std::max(last_id_, d.id);
      d.status = "unconfirmed";
      d.note.clear();
      d.created = d.updated = now;
      d.seq = ++last_seq_;
      Store(d);
      detections_[d.id] = d;
      seen.insert(d.id);
      result.ids.push_back(d.id);
      ++result.created;
      Announce("created", d);
    }
  }
  if (!options.replace_model.empty())
    for (auto it = detections_.begin(); it != detections_.end();) {
      auto next = std::next(it);
      const Detection& d = it->second;
      if (d.source != "operator" && d.model == options.replace_model && d.status == "unconfirmed" &&
          !seen.count(d.id)) {
        Forget(it);
        ++result.deleted;
      }
      it = next;
    }
  store_->Flush();
  return result;
}

PackedDetections DetectionRegistry::Pack(const DetectionFilter& f, size_t max, std::optional<double> t0) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<std::pair<const Detection*, bool>> chosen;  // detection, deleted
  for (const auto& [id, d] : detections_)
    if (Passes(f, d)) chosen.push_back({&d, false});
  for (const auto& [id, d] : deleted_)
    if (Passes(f, d)) chosen.push_back({&d, true});
  std::sort(chosen.begin(), chosen.end(), [](const auto& a, const auto& b) { return a.first->seq < b.first->seq; });
  PackedDetections out;
  out.last_seq = last_seq_;
  if (chosen.size() > max) {
    chosen.resize(max);
    out.last_seq = chosen.empty() ? f.since.value_or(0) : chosen.back().first->seq;
  }
  for (const auto& [d, deleted] : chosen) {
    const auto class_id = static_cast<uint8_t>(ClassId(classes_, d->class_name));
    const auto bytes = EncodeModemRecord(ModemRecordOf(*d, class_id, t0, deleted));
    out.bytes.insert(out.bytes.end(), bytes.begin(), bytes.end());
  }
  out.count = chosen.size();
  return out;
}

std::vector<std::string> DetectionRegistry::Classes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return classes_;
}

}  // namespace seamap::server
