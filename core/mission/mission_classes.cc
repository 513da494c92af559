#include "core/mission/mission_classes.h"

#include <algorithm>

namespace seamap {

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
  std::vector<std::string> table = ReadMissionMetadata(store).classes.value_or(std::vector<std::string>{});
  for (const Detection& d : store.Records().Detections()) ExtendClassTable(&table, {d.class_name});
  return table;
}

void StoreClassTable(TileStore* store, const std::vector<std::string>& table) {
  MissionMetadata m;
  m.classes = table;
  WriteMissionMetadata(store, m);
}

namespace {

std::optional<double> FirstFrameTime(const TileStore& store) {
  for (const FrameRecord& f : store.Records().Frames())  // in id order
    if (f.time_s) return f.time_s;
  return std::nullopt;
}

}  // namespace

std::optional<double> MissionT0(const TileStore& store) {
  if (auto t0 = ReadMissionMetadata(store).t0) return t0;
  return FirstFrameTime(store);
}

std::optional<double> StoreMissionT0(TileStore* store) {
  const MissionMetadata stored = ReadMissionMetadata(*store);
  // A stored text that does not read is not replaced (as before): the frames give t0.
  if (stored.t0 || stored.unreadable.count(kT0Key)) return stored.t0 ? stored.t0 : FirstFrameTime(*store);
  MissionMetadata m;
  m.t0 = FirstFrameTime(*store);
  if (m.t0) WriteMissionMetadata(store, m);
  return m.t0;
}

}  // namespace seamap
