#include "core/tiles/mission_classes.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include <nlohmann/json.hpp>

namespace seamap {

std::vector<std::string> ClassTableFromMetadata(const std::map<std::string, std::string>& metadata) {
  auto it = metadata.find(kClassTableKey);
  if (it == metadata.end()) return {};
  const nlohmann::json j = nlohmann::json::parse(it->second, nullptr, /*allow_exceptions=*/false);
  std::vector<std::string> out;
  if (!j.is_array()) return out;
  for (const auto& name : j)
    if (name.is_string()) out.push_back(name.get<std::string>());
  return out;
}

bool ExtendClassTable(std::vector<std::string>* table, const std::vector<std::string>& names) {
  bool grew = false;
  for (const std::string& name : names) {
    if (name.empty() || std::find(table->begin(), table->end(), name) != table->end()) continue;
    table->push_back(name);
    grew = true;
  }
  return grew;
}

int ClassId(const std::vector<std::string>& table, const std::string& name) {
  auto it = std::find(table.begin(), table.end(), name);
  const auto index = it - table.begin();
  return it == table.end() || index >= 255 ? 255 : static_cast<int>(index);
}

std::vector<std::string> MissionClassTable(const TileStore& store) {
  std::vector<std::string> table = ClassTableFromMetadata(store.Metadata());
  for (const Detection& d : store.Detections()) ExtendClassTable(&table, {d.class_name});
  return table;
}

void StoreClassTable(TileStore* store, const std::vector<std::string>& table) {
  store->SetMetadata(kClassTableKey, nlohmann::json(table).dump());
}

std::optional<double> MissionT0(const TileStore& store) {
  const auto metadata = store.Metadata();
  auto it = metadata.find(kT0Key);
  if (it != metadata.end()) {
    char* end = nullptr;
    const double v = std::strtod(it->second.c_str(), &end);
    if (end != it->second.c_str() && *end == '\0') return v;
  }
  for (const FrameRecord& f : store.Frames())  // in id order
    if (f.time_s) return f.time_s;
  return std::nullopt;
}

std::optional<double> StoreMissionT0(TileStore* store) {
  if (store->Metadata().count(kT0Key)) return MissionT0(*store);
  const std::optional<double> t0 = MissionT0(*store);
  if (t0) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", *t0);
    store->SetMetadata(kT0Key, text);
  }
  return t0;
}

}  // namespace seamap
