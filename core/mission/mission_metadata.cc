#include "core/mission/mission_metadata.h"

#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/tiles/tile_store.h"
#include "core/util/error.h"

namespace seamap {
namespace {

// Numbers as the builder has always written them (10 significant digits).
std::string Number(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

std::optional<double> ParseDouble(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0') return std::nullopt;
  return v;
}

std::optional<int> ParseInt(const std::string& text) {
  char* end = nullptr;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (end == text.c_str() || *end != '\0' || v < INT32_MIN || v > INT32_MAX) return std::nullopt;
  return static_cast<int>(v);
}

std::vector<std::string> SplitLayers(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');)
    if (!part.empty()) out.push_back(part);
  return out;
}

}  // namespace

std::vector<std::string> MissionMetadata::LayersOrRaw() const {
  if (layers && !layers->empty()) return *layers;
  return {"raw"};
}

std::vector<std::string> MissionMetadata::ExtraLayers() const {
  if (!layers || layers->size() < 2) return {};
  return std::vector<std::string>(layers->begin() + 1, layers->end());
}

std::string LayerListText(const std::vector<std::string>& layers) {
  std::string out;
  for (const std::string& l : layers) out += (out.empty() ? "" : ",") + l;
  return out;
}

MissionMetadata ReadMissionMetadata(const std::map<std::string, std::string>& metadata) {
  MissionMetadata m;
  auto text = [&](const char* key) -> const std::string* {
    auto it = metadata.find(key);
    return it == metadata.end() ? nullptr : &it->second;
  };
  // Sets `field` from the key's text when it reads; notes the key otherwise.
  auto read = [&](const char* key, auto& field, auto parse) {
    const std::string* t = text(key);
    if (!t) return;
    if (auto v = parse(*t))
      field = *v;
    else
      m.unreadable.insert(key);
  };
  if (const std::string* t = text(kStateKey)) m.state = *t;
  if (const std::string* t = text(kLayersKey)) m.layers = SplitLayers(*t);
  read(kOriginKey, m.origin, [](const std::string& t) -> std::optional<LatLon> {
    double lat = 0, lon = 0;
    if (std::sscanf(t.c_str(), "%lf,%lf", &lat, &lon) != 2) return std::nullopt;
    return LatLon{lat, lon};
  });
  read(kTrajectoryKey, m.trajectory, [](const std::string& t) -> std::optional<nlohmann::json> {
    nlohmann::json j = nlohmann::json::parse(t, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded()) return std::nullopt;
    return j;
  });
  read(kReliefKey, m.relief, [](const std::string& t) -> std::optional<nlohmann::json> {
    nlohmann::json j = nlohmann::json::parse(t, nullptr, /*allow_exceptions=*/false);
    if (!j.is_object()) return std::nullopt;
    return j;
  });
  read(kT0Key, m.t0, ParseDouble);
  read(kClassTableKey, m.classes, [](const std::string& t) -> std::optional<std::vector<std::string>> {
    const nlohmann::json j = nlohmann::json::parse(t, nullptr, /*allow_exceptions=*/false);
    if (!j.is_array()) return std::nullopt;
    std::vector<std::string> out;
    for (const auto& name : j)
      if (name.is_string()) out.push_back(name.get<std::string>());
    return out;
  });
  read(kTileSizeKey, m.tile_size_px, ParseInt);
  read(kGsdKey, m.gsd_m, ParseDouble);
  read(kChannelsKey, m.channels, ParseInt);
  read(kFramesUsedKey, m.frames_used, ParseInt);
  read(kFramesRejectedKey, m.frames_rejected, ParseInt);
  return m;
}

MissionMetadata ReadMissionMetadata(const TileStore& store) {
  return ReadMissionMetadata(store.Metadata());
}

void WriteMissionMetadata(TileStore* store, const MissionMetadata& m) {
  if (m.tile_size_px) store->SetMetadata(kTileSizeKey, std::to_string(*m.tile_size_px));
  if (m.gsd_m) store->SetMetadata(kGsdKey, Number(*m.gsd_m));
  if (m.channels) store->SetMetadata(kChannelsKey, std::to_string(*m.channels));
  if (m.origin) store->SetMetadata(kOriginKey, Number(m.origin->lat) + "," + Number(m.origin->lon));
  if (m.state) store->SetMetadata(kStateKey, *m.state);
  if (m.frames_used) store->SetMetadata(kFramesUsedKey, std::to_string(*m.frames_used));
  if (m.frames_rejected) store->SetMetadata(kFramesRejectedKey, std::to_string(*m.frames_rejected));
  if (m.layers) store->SetMetadata(kLayersKey, LayerListText(*m.layers));
  if (m.trajectory) store->SetMetadata(kTrajectoryKey, m.trajectory->dump());
  if (m.classes) store->SetMetadata(kClassTableKey, nlohmann::json(*m.classes).dump());
  if (m.relief) store->SetMetadata(kReliefKey, m.relief->dump());
  if (m.t0) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", *m.t0);
    store->SetMetadata(kT0Key, text);
  }
}

LatLon RequireMissionOrigin(const MissionMetadata& metadata, const std::string& path) {
  if (!metadata.origin) throw InputError(path, 0, kOriginKey, "the map's metadata has no mission origin (lat,lon)");
  return *metadata.origin;
}

}  // namespace seamap
