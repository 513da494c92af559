#include "core/mission/detection_book.h"

#include <algorithm>
#include <set>

#include "core/mission/detection_match.h"
#include "core/mission/mission_classes.h"
#include "core/mission/mission_metadata.h"
#include "core/mission/operator_box.h"
#include "core/tiles/modem_record.h"
#include "core/tiles/record_json.h"
#include "core/util/utc_time.h"

namespace seamap {
namespace {

constexpr size_t kMaxClassLength = 64;
constexpr size_t kMaxNoteLength = 4000;

using Kind = DetectionError::Kind;

DetectionError Refused(const std::string& message) {
  return {Kind::kRefused, "", message, message};
}

// The "type" member, or "" when missing or not a string (value() would throw
// nlohmann's type_error, a server error instead of a bad request).
std::string TypeOf(const nlohmann::json& j) {
  auto it = j.find("type");
  return it != j.end() && it->is_string() ? it->get<std::string>() : "";
}

// Geometry of a Feature: a Point [lon, lat] (an altitude is allowed and ignored).
LatLon ParsePoint(const nlohmann::json& geometry) {
  if (!geometry.is_object() || TypeOf(geometry) != "Point")
    throw DetectionError::Invalid("geometry", "expected a GeoJSON Point");
  const auto& c = geometry.contains("coordinates") ? geometry["coordinates"] : nlohmann::json();
  if (!c.is_array() || c.size() < 2 || c.size() > 3 || !c[0].is_number() || !c[1].is_number())
    throw DetectionError::Invalid("geometry.coordinates", "expected [lon, lat]");
  const double lon = c[0].get<double>(), lat = c[1].get<double>();
  if (!(lon >= -180 && lon <= 180) || !(lat >= -90 && lat <= 90))
    throw DetectionError::Invalid("geometry.coordinates", "lon must be in [-180, 180] and lat in [-90, 90]");
  return {lat, lon};
}

// Applies the writable properties; read-only ones a client echoes back are ignored.
// `box` and `size_m` are an operator's box (operator_box.h; a recogniser's stay as found).
void ApplyProperties(const nlohmann::json& props, Detection* d) {
  if (!props.is_object()) throw DetectionError::Invalid("properties", "expected an object");
  static const std::set<std::string> kReadOnly = {
      "id",     "source", "created",   "updated",   "seq",         "frame_id", "model",   "level",
      "levels", "frames", "truncated", "alt_class", "heading_deg", "depth_m",  "sigma_m", "position_m"};
  for (const auto& [key, value] : props.items()) {
    if (key == "class") {
      if (!value.is_string() || value.get<std::string>().empty() || value.get<std::string>().size() > kMaxClassLength)
        throw DetectionError::Invalid("properties.class", "expected a non-empty string of at most 64 characters");
      d->class_name = value.get<std::string>();
    } else if (key == "note") {
      if (!value.is_string() || value.get<std::string>().size() > kMaxNoteLength)
        throw DetectionError::Invalid("properties.note", "expected a string of at most 4000 characters");
      d->note = value.get<std::string>();
    } else if (key == "score") {
      if (!value.is_number() || value.get<double>() < 0 || value.get<double>() > 1)
        throw DetectionError::Invalid("properties.score", "expected a number in [0, 1]");
      d->score = value.get<double>();
    } else if (key == "status") {
      if (!value.is_string() || !IsDetectionStatus(value.get<std::string>()))
        throw DetectionError::Invalid("properties.status", "expected \"unconfirmed\", \"confirmed\" or \"rejected\"");
      d->status = value.get<std::string>();
    } else if (key == "time_s") {
      if (value.is_null())
        d->time_s.reset();
      else if (value.is_number())
        d->time_s = value.get<double>();
      else
        throw DetectionError::Invalid("properties.time_s", "expected a number of seconds or null");
    } else if (key != "box" && key != "size_m" && !kReadOnly.count(key)) {
      throw DetectionError::Invalid("properties." + key,
                                    "unknown property; expected class, note, score, status, time_s, box or size_m");
    }
  }
  const auto box = props.find("box"), size = props.find("size_m");
  if (d->source == "operator")
    ApplyOperatorBox(box == props.end() ? nullptr : &*box, size == props.end() ? nullptr : &*size, d);
}

// A recogniser's detection allows `status` and `note` to change; any other
// property may be echoed back unchanged, but not changed.
void CheckRecogniserPatch(const Detection& d, const nlohmann::json& patch) {
  const std::string who = "detection " + std::to_string(d.id) + " comes from the " + d.source;
  auto refuse = [&](const std::string& what) {
    throw Refused(who + "; only its status and note can be changed, not " + what);
  };
  const bool feature = TypeOf(patch) == "Feature";
  if (feature && patch.contains("geometry") && !patch["geometry"].is_null()) {
    const LatLon p = ParsePoint(patch["geometry"]);
    if (p.lat != d.position.lat || p.lon != d.position.lon) refuse("its position");
  }
  const nlohmann::json& props =
      feature ? (patch.contains("properties") ? patch["properties"] : nlohmann::json()) : patch;
  if (props.is_null()) return;
  if (!props.is_object()) throw DetectionError::Invalid("properties", "expected an object");
  const nlohmann::json current = DetectionToJson(d);
  for (const auto& [key, value] : props.items()) {
    if (key == "status" || key == "note") continue;
    auto it = current.find(key);
    if (it == current.end() || *it != value) refuse("'" + key + "'");
  }
}

DetectionError NotFound(int64_t id) {
  const std::string message = "no detection " + std::to_string(id);
  return {Kind::kNotFound, "id", message, message};
}

}  // namespace

void DetectionBook::LoadReadable(const TileStore& store, std::vector<int64_t>* unreadable) {
  std::lock_guard<std::mutex> lock(mutex_);
  const std::vector<Detection> readable = store.Records().ReadableDetections(unreadable);
  for (const Detection& d : readable) {
    detections_[d.id] = d;
    stored_seq_[d.id] = d.seq;
    last_seq_ = std::max(last_seq_, d.seq);
    last_id_ = std::max(last_id_, d.id);
  }
  if (unreadable)
    for (int64_t id : *unreadable) last_id_ = std::max(last_id_, id);  // never reused
  // MissionClassTable's table, from the records that could be read.
  classes_ = ReadMissionMetadata(store).classes.value_or(std::vector<std::string>{});
  for (const Detection& d : readable) ExtendClassTable(&classes_, {d.class_name});
}

void DetectionBook::Load(const TileStore& store) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (Detection& d : store.Records().Detections()) {
    stored_seq_[d.id] = d.seq;
    last_seq_ = std::max(last_seq_, d.seq);
    last_id_ = std::max(last_id_, d.id);
    const int64_t id = d.id;
    detections_[id] = std::move(d);  // moved: one copy of a long list in memory, not two
  }
  unreadable_ = store.Records().SkippedDetections();
  classes_ = MissionClassTable(store);
}

void DetectionBook::Refresh(const TileStore& store) {
  std::lock_guard<std::mutex> lock(mutex_);
  RefreshLocked(store);
}

void DetectionBook::RefreshLocked(const TileStore& store) {
  std::map<int64_t, Detection> in_store;
  for (Detection& d : store.Records().Detections()) in_store[d.id] = std::move(d);
  unreadable_ = store.Records().SkippedDetections();
  for (auto& [id, d] : in_store) {
    last_id_ = std::max(last_id_, id);
    auto seen = stored_seq_.find(id);
    if (seen != stored_seq_.end() && seen->second == d.seq) continue;
    stored_seq_[id] = d.seq;
    // The other process numbered it from the file alone; readers asking
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

std::vector<Detection> DetectionBook::Query(const DetectionFilter& f, int64_t* last_seq) const {
  std::vector<Detection> out;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [id, d] : detections_)
    if (Passes(f, d)) out.push_back(d);
  if (last_seq) *last_seq = last_seq_;
  return out;
}

DetectionPage DetectionBook::QueryPage(const DetectionFilter& f, std::optional<int64_t> after_id, size_t limit) const {
  DetectionPage page;
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto it = after_id ? detections_.upper_bound(*after_id) : detections_.begin(); it != detections_.end(); ++it) {
    if (!Passes(f, it->second)) continue;
    if (page.detections.size() >= limit) {
      page.more = true;
      break;
    }
    page.detections.push_back(it->second);
  }
  page.last_seq = last_seq_;
  return page;
}

std::optional<Detection> DetectionBook::Get(int64_t id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = detections_.find(id);
  if (it == detections_.end()) return std::nullopt;
  return it->second;
}

void DetectionBook::CheckWritable() const {
  if (!store_) throw Refused("this mission is open read-only; detections cannot be changed");
}

void DetectionBook::Announce(const char* action, const Detection& d) {
  if (listener_) listener_(action, d);
}

void DetectionBook::Store(const Detection& d) {
  store_->Records().PutDetection(d);
  stored_seq_[d.id] = d.seq;
  if (ExtendClassTable(&classes_, {d.class_name})) StoreClassTable(store_, classes_);
  if (!t0_stored_) t0_stored_ = StoreMissionT0(store_).has_value();
}

void DetectionBook::Forget(std::map<int64_t, Detection>::iterator it) {
  Detection gone = it->second;
  store_->Records().DeleteDetection(gone.id);
  stored_seq_.erase(gone.id);
  detections_.erase(it);
  gone.seq = ++last_seq_;
  deleted_[gone.id] = gone;
  Announce("deleted", gone);
}

Detection DetectionBook::Create(const nlohmann::json& feature) {
  CheckWritable();
  if (!feature.is_object() || TypeOf(feature) != "Feature")
    throw DetectionError::Invalid("body", "expected a GeoJSON Feature with a Point geometry");
  Detection d;
  d.position = ParsePoint(feature.contains("geometry") ? feature["geometry"] : nlohmann::json());
  d.status = "confirmed";  // an operator's own mark, unless the body says otherwise
  d.source = "operator";
  ApplyProperties(feature.contains("properties") ? feature["properties"] : nlohmann::json::object(), &d);
  if (d.class_name.empty()) throw DetectionError::Invalid("properties.class", "required (what the object is)");
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
  return d;
}

Detection DetectionBook::Update(int64_t id, const nlohmann::json& patch) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  RefreshLocked(*store_);
  auto it = detections_.find(id);
  if (it == detections_.end()) throw NotFound(id);
  if (!patch.is_object()) throw DetectionError::Invalid("body", "expected a GeoJSON Feature or a properties object");
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
  return d;
}

void DetectionBook::Delete(int64_t id) {
  CheckWritable();
  std::lock_guard<std::mutex> lock(mutex_);
  RefreshLocked(*store_);
  auto it = detections_.find(id);
  if (it == detections_.end()) throw NotFound(id);
  if (it->second.source != "operator")
    throw Refused("detection " + std::to_string(id) + " comes from the " + it->second.source +
                  "; it cannot be deleted, only rejected (PATCH status \"rejected\")");
  Forget(it);
  store_->Flush();
}

PublishResult DetectionBook::Publish(std::vector<Detection> batch, const PublishOptions& options) {
  CheckWritable();
  PublishResult result;
  const std::string now = UtcNowIso8601();
  std::lock_guard<std::mutex> lock(mutex_);
  RefreshLocked(*store_);
  if (ExtendClassTable(&classes_, options.model_classes)) StoreClassTable(store_, classes_);
  if (!t0_stored_) t0_stored_ = StoreMissionT0(store_).has_value();
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
  if (!options.replace_model.empty()) {
    const std::string file = ModelFile(options.replace_model);
    for (auto it = detections_.begin(); it != detections_.end();) {
      auto next = std::next(it);
      const Detection& d = it->second;
      if (d.source != "operator" && ModelFile(d.model) == file && d.status == "unconfirmed" && !seen.count(d.id)) {
        Forget(it);
        ++result.deleted;
      }
      it = next;
    }
  }
  store_->Flush();
  return result;
}

PackedDetections DetectionBook::Pack(const DetectionFilter& f, size_t max, std::optional<double> t0) const {
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

std::vector<std::string> DetectionBook::Classes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return classes_;
}

std::vector<Detection> PublishFound(TileStore& store, std::vector<Detection> found, const std::string& model,
                                    const std::vector<std::string>& class_names) {
  DetectionBook book(&store);
  book.Load(store);
  PublishOptions options;
  options.model_classes = class_names;
  options.replace_model = model;
  const PublishResult result = book.Publish(std::move(found), options);
  std::vector<Detection> stored;
  for (int64_t id : result.ids) stored.push_back(*book.Get(id));
  return stored;
}

}  // namespace seamap
