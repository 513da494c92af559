#include "core/tiles/record_json.h"

namespace seamap {
namespace {

nlohmann::json OptionalToJson(const std::optional<double>& v) {
  return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

std::optional<double> OptionalFromJson(const nlohmann::json& j, const char* key) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return std::nullopt;
  return it->get<double>();
}

bool HasNumber(const nlohmann::json& j, const char* key) {
  auto it = j.find(key);
  return it != j.end() && it->is_number();
}

}  // namespace

nlohmann::json FootprintToJson(const std::array<LatLon, 4>& footprint) {
  nlohmann::json out = nlohmann::json::array();
  for (const LatLon& c : footprint) out.push_back({c.lon, c.lat});
  return out;
}

std::array<LatLon, 4> FootprintFromJson(const nlohmann::json& j) {
  std::array<LatLon, 4> out{};
  for (size_t i = 0; i < out.size() && i < j.size(); ++i)
    out[i] = {j.at(i).at(1).get<double>(), j.at(i).at(0).get<double>()};
  return out;
}

nlohmann::json FrameToJson(const FrameRecord& f) {
  nlohmann::json j = {{"id", f.id},
                      {"image", f.image},
                      {"image_path", f.image_path},
                      {"time_s", OptionalToJson(f.time_s)},
                      {"lat", f.position.lat},
                      {"lon", f.position.lon},
                      {"altitude_m", f.altitude_m},
                      {"depth_m", f.depth_m},
                      {"heading_deg", f.heading_deg},
                      {"pitch_deg", f.pitch_deg},
                      {"roll_deg", f.roll_deg},
                      {"footprint", FootprintToJson(f.footprint)},
                      {"status", f.status}};
  if (f.nav) {
    const NavigatedPose& n = *f.nav;
    j["nav_lat"] = n.position.lat;
    j["nav_lon"] = n.position.lon;
    j["nav_altitude_m"] = n.altitude_m;
    j["nav_depth_m"] = n.depth_m;
    j["nav_heading_deg"] = n.heading_deg;
    j["nav_pitch_deg"] = n.pitch_deg;
    j["nav_roll_deg"] = n.roll_deg;
  }
  return j;
}

FrameRecord FrameFromJson(const nlohmann::json& j) {
  FrameRecord f;
  f.id = j.at("id").get<int>();
  f.image = j.value("image", "");
  f.image_path = j.value("image_path", "");
  f.time_s = OptionalFromJson(j, "time_s");
  f.position = {j.at("lat").get<double>(), j.at("lon").get<double>()};
  f.altitude_m = j.value("altitude_m", 0.0);
  f.depth_m = j.value("depth_m", 0.0);
  f.heading_deg = j.value("heading_deg", 0.0);
  f.pitch_deg = j.value("pitch_deg", 0.0);
  f.roll_deg = j.value("roll_deg", 0.0);
  if (j.contains("footprint")) f.footprint = FootprintFromJson(j.at("footprint"));
  f.status = j.value("status", "");
  if (HasNumber(j, "nav_lat") && HasNumber(j, "nav_lon")) {
    NavigatedPose& n = f.nav.emplace();
    n.position = {j.at("nav_lat").get<double>(), j.at("nav_lon").get<double>()};
    n.altitude_m = j.value("nav_altitude_m", 0.0);
    n.depth_m = j.value("nav_depth_m", 0.0);
    n.heading_deg = j.value("nav_heading_deg", 0.0);
    n.pitch_deg = j.value("nav_pitch_deg", 0.0);
    n.roll_deg = j.value("nav_roll_deg", 0.0);
  }
  return f;
}

nlohmann::json TrackPointToJson(const TrackPoint& p) {
  nlohmann::json j = {{"seq", p.seq},
                      {"time_s", OptionalToJson(p.time_s)},
                      {"lat", p.position.lat},
                      {"lon", p.position.lon},
                      {"altitude_m", p.altitude_m},
                      {"depth_m", p.depth_m},
                      {"heading_deg", p.heading_deg}};
  if (p.nav) {
    j["nav_lat"] = p.nav->position.lat;
    j["nav_lon"] = p.nav->position.lon;
    j["nav_heading_deg"] = p.nav->heading_deg;
  }
  return j;
}

TrackPoint TrackPointFromJson(const nlohmann::json& j) {
  TrackPoint p;
  p.seq = j.at("seq").get<int>();
  p.time_s = OptionalFromJson(j, "time_s");
  p.position = {j.at("lat").get<double>(), j.at("lon").get<double>()};
  p.altitude_m = j.value("altitude_m", 0.0);
  p.depth_m = j.value("depth_m", 0.0);
  p.heading_deg = j.value("heading_deg", 0.0);
  if (HasNumber(j, "nav_lat") && HasNumber(j, "nav_lon"))
    p.nav = NavigatedPosition{{j.at("nav_lat").get<double>(), j.at("nav_lon").get<double>()},
                              j.value("nav_heading_deg", 0.0)};
  return p;
}

nlohmann::json BoxToJson(const std::vector<LatLon>& ring) {
  nlohmann::json out = nlohmann::json::array();
  for (const LatLon& c : ring) out.push_back({c.lon, c.lat});
  return out;
}

std::vector<LatLon> BoxFromJson(const nlohmann::json& j) {
  std::vector<LatLon> out;
  if (!j.is_array()) return out;
  for (const auto& c : j) out.push_back({c.at(1).get<double>(), c.at(0).get<double>()});
  return out;
}

nlohmann::json PairToJson(const std::optional<std::array<double, 2>>& v) {
  return v ? nlohmann::json({(*v)[0], (*v)[1]}) : nlohmann::json(nullptr);
}

std::optional<std::array<double, 2>> PairFromJson(const nlohmann::json& j) {
  if (!j.is_array() || j.size() != 2) return std::nullopt;
  return std::array<double, 2>{j[0].get<double>(), j[1].get<double>()};
}

nlohmann::json DetectionToJson(const Detection& original) {
  Detection d = original;
  NormaliseDetection(&d);
  return {{"id", d.id},
          {"class", d.class_name},
          {"score", d.score},
          {"lat", d.position.lat},
          {"lon", d.position.lon},
          {"note", d.note},
          {"source", d.source},
          {"model", d.model},
          {"level", d.level ? nlohmann::json(*d.level) : nlohmann::json(nullptr)},
          {"levels", d.levels},
          {"box", d.box.empty() ? nlohmann::json(nullptr) : BoxToJson(d.box)},
          {"position_m", PairToJson(d.position_m)},
          {"size_m", PairToJson(d.size_m)},
          {"frames", d.frames},
          {"frame_id", d.frame_id ? nlohmann::json(*d.frame_id) : nlohmann::json(nullptr)},
          {"time_s", OptionalToJson(d.time_s)},
          {"status", d.status},
          {"truncated", d.truncated},
          {"alt_class", d.alt_class.empty() ? nlohmann::json(nullptr) : nlohmann::json(d.alt_class)},
          {"heading_deg", OptionalToJson(d.heading_deg)},
          {"depth_m", OptionalToJson(d.depth_m)},
          {"sigma_m", OptionalToJson(d.sigma_m)},
          {"created", d.created},
          {"updated", d.updated},
          {"seq", d.seq}};
}

nlohmann::json DetectionFeature(const Detection& d) {
  nlohmann::json props = DetectionToJson(d);
  props.erase("lat");  // the Point geometry carries them
  props.erase("lon");
  return {{"type", "Feature"},
          {"id", d.id},
          {"geometry", {{"type", "Point"}, {"coordinates", {d.position.lon, d.position.lat}}}},
          {"properties", std::move(props)}};
}

Detection DetectionFromJson(const nlohmann::json& j) {
  Detection d;
  d.id = j.at("id").get<int64_t>();
  d.class_name = j.at("class").get<std::string>();
  d.score = j.value("score", 1.0);
  d.position = {j.at("lat").get<double>(), j.at("lon").get<double>()};
  d.note = j.value("note", "");
  d.source = j.value("source", "operator");
  d.model = j.value("model", "");
  if (HasNumber(j, "level")) d.level = j.at("level").get<int>();
  if (j.contains("levels") && j.at("levels").is_array()) d.levels = j.at("levels").get<std::vector<int>>();
  if (j.contains("box")) d.box = BoxFromJson(j.at("box"));
  if (j.contains("position_m")) d.position_m = PairFromJson(j.at("position_m"));
  if (j.contains("size_m")) d.size_m = PairFromJson(j.at("size_m"));
  if (j.contains("frames") && j.at("frames").is_array()) d.frames = j.at("frames").get<std::vector<int>>();
  if (HasNumber(j, "frame_id")) d.frame_id = j.at("frame_id").get<int>();
  d.time_s = OptionalFromJson(j, "time_s");
  d.status = j.contains("status") && j.at("status").is_string() ? j.at("status").get<std::string>() : "";
  d.truncated = j.contains("truncated") && j.at("truncated").is_boolean() && j.at("truncated").get<bool>();
  if (j.contains("alt_class") && j.at("alt_class").is_string()) d.alt_class = j.at("alt_class").get<std::string>();
  d.heading_deg = OptionalFromJson(j, "heading_deg");
  d.depth_m = OptionalFromJson(j, "depth_m");
  d.sigma_m = OptionalFromJson(j, "sigma_m");
  d.created = j.value("created", "");
  d.updated = j.value("updated", "");
  d.seq = j.value("seq", int64_t{0});
  NormaliseDetection(&d);
  return d;
}

}  // namespace seamap
