#pragma once
// Two mission-wide references the compact modem record needs, kept in the
// mission's metadata (core/mission/mission_metadata.h): the class table
// (class id = index; the model's names in order, then other classes as they
// first appear; append-only, so an id once sent over the acoustic link keeps
// its meaning) and t0, the time of the mission's first frame (record times
// count tenths of a second from it).
#include <optional>
#include <string>
#include <vector>

#include "core/mission/mission_metadata.h"
#include "core/tiles/tile_store.h"

namespace seamap {

// Appends the names the table lacks, in order; true when it grew.
bool ExtendClassTable(std::vector<std::string>* table, const std::vector<std::string>& names);
// The index of `name`, or 255 (unknown) when absent or beyond 254.
int ClassId(const std::vector<std::string>& table, const std::string& name);
// The stored table, extended by the classes of the stored detections in id
// order (a mission written before the table existed).
std::vector<std::string> MissionClassTable(const TileStore& store);
// Writes the table to the metadata (no flush).
void StoreClassTable(TileStore* store, const std::vector<std::string>& table);

// The stored t0, else the time of the first frame (by id) that has one.
std::optional<double> MissionT0(const TileStore& store);
// Stores t0 when the metadata lacks it and a frame gives it; the value (no flush).
std::optional<double> StoreMissionT0(TileStore* store);

}  // namespace seamap
