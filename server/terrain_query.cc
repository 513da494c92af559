#include "server/terrain_query.h"

#include <cstdio>

#include "server/api_error.h"

namespace seamap::server {

TerrainQuery::TerrainQuery(MissionTerrain terrain)
    : terrain_(std::move(terrain)), frame_(terrain_.origin), datum_(UserDatum(terrain_.grid)) {}

nlohmann::json TerrainQuery::At(LatLon point) const {
  const HeightGrid& g = terrain_.grid;
  const LocalXY p = frame_.FromLatLon(point);
  double height = 0, sigma = 0;
  if (!g.Sample(p, &height, &sigma)) {
    double row = 0, col = 0;
    g.CellOf(p, &row, &col);
    const bool inside = row >= 0 && col >= 0 && row <= g.rows() - 1 && col <= g.cols() - 1;
    char where[96];
    std::snprintf(where, sizeof where, "%.7f,%.7f (%.2f m east, %.2f m north of the origin)", point.lat, point.lon,
                  p.east, p.north);
    throw ApiError(
        404, std::string("no height at ") + where +
                 (inside ? ": a hole in the height model (no seabed points there)" : ": outside the height model"));
  }
  return {{"height_m", height + datum_.offset_m},
          {"sigma_m", sigma},
          {"datum", datum_.name},
          {"lat", point.lat},
          {"lon", point.lon}};
}

nlohmann::json TerrainQuery::Summary() const {
  return {{"datum", datum_.name},
          {"cell_m", terrain_.grid.cell_m},
          {"rows", terrain_.grid.rows()},
          {"cols", terrain_.grid.cols()}};
}

}  // namespace seamap::server
