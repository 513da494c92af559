#pragma once
// The operator's "how deep is it there?" (GET /api/terrain?lat=&lon=): the
// mission's height model (core/mission/mission_terrain.h) sampled bilinearly
// (HeightGrid::Sample) at a point, in the user's datum (sea surface, else the
// survey's mean seabed). Immutable once made: shared by request threads.
#include <string>

#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/mission/mission_terrain.h"
#include "core/terrain/height_datum.h"

namespace seamap::server {

class TerrainQuery {
 public:
  explicit TerrainQuery(MissionTerrain terrain);

  // {height_m, sigma_m, datum, lat, lon}; throws ApiError 404 with the
  // reason where the model says nothing (outside it, or in a hole).
  nlohmann::json At(LatLon point) const;
  // {datum, cell_m, rows, cols}: what the model is, for the status.
  nlohmann::json Summary() const;

 private:
  MissionTerrain terrain_;
  LocalFrame frame_;
  HeightDatum datum_;
};

}  // namespace seamap::server
