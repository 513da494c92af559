// seed_terrain MISSION [--no-depth | --from TERRAIN.tif]: stores a synthetic height model in a
// built mission and draws its relief layer (StoreMissionTerrain, what
// `build --terrain` calls), for the console's browser test and the bench,
// until the build estimates one: 5 cm cells over the frames' footprints, the
// seabed at the frames' depth + altitude with a 0.4 m mound and ripples, a
// hole in the south-west. --no-depth: heights without a depth datum.
// --from: the height model of a GeoTIFF instead (e.g. `simulate --relief`'s
// truth/terrain.tif; core/terrain/height_grid_io.h), probed at its centre.
// Prints JSON: {low_m, high_m, datum, probe: {lat, lon, height_m, sigma_m}}
// (the probe at the mound's top, heights in the user's datum).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/mission/mission_metadata.h"
#include "core/mission/relief_layer.h"
#include "core/terrain/height_datum.h"
#include "core/terrain/height_grid_io.h"
#include "core/tiles/tile_store.h"

int main(int argc, char** argv) {
  using namespace seamap;
  const bool no_depth = argc == 3 && std::strcmp(argv[2], "--no-depth") == 0;
  const bool from_file = argc == 4 && std::strcmp(argv[2], "--from") == 0;
  if (argc != 2 && !no_depth && !from_file) {
    std::fprintf(stderr, "usage: seed_terrain MISSION [--no-depth | --from TERRAIN.tif]\n");
    return 2;
  }
  try {
    std::unique_ptr<TileStore> store = OpenExistingMap(argv[1], /*writable=*/true);
    const LatLon origin = RequireMissionOrigin(ReadMissionMetadata(*store), argv[1]);
    const LocalFrame frame(origin);
    if (from_file) {
      MissionTerrain t{ReadHeightGridGeotiff(argv[3], origin), origin};
      StoreMissionTerrain(store.get(), t, false);
      const HeightGrid& g = t.grid;
      const LocalXY centre = g.CellCentre(g.rows() / 2, g.cols() / 2);
      double height = 0, sigma = 0;
      if (!g.Sample(centre, &height, &sigma)) throw std::runtime_error("the model has a hole at its centre");
      const nlohmann::json relief = *ReadMissionMetadata(*store).relief;
      const LatLon probe = frame.ToLatLon(centre);
      std::printf("%s\n", nlohmann::json({{"low_m", relief["low_m"]},
                                          {"high_m", relief["high_m"]},
                                          {"datum", relief["datum"]},
                                          {"probe",
                                           {{"lat", probe.lat},
                                            {"lon", probe.lon},
                                            {"height_m", height + UserDatum(g).offset_m},
                                            {"sigma_m", sigma}}}})
                              .dump()
                              .c_str());
      return 0;
    }
    double w = std::numeric_limits<double>::infinity(), e = -w, s = w, n = -w, seabed = 0;
    int used = 0;
    for (const FrameRecord& f : store->Records().Frames()) {
      if (f.status != "used") continue;
      for (const LatLon& corner : f.footprint) {
        const LocalXY p = frame.FromLatLon(corner);
        w = std::min(w, p.east), e = std::max(e, p.east), s = std::min(s, p.north), n = std::max(n, p.north);
      }
      seabed += -((no_depth ? 0 : f.depth_m) + f.altitude_m);  // without depth: the vehicle at 0
      ++used;
    }
    if (used == 0) throw std::runtime_error("the mission has no used frames");
    seabed /= used;
    MissionTerrain t;
    t.origin = origin;
    HeightGrid& g = t.grid;
    g.cell_m = 0.05;
    g.east0_m = w;
    g.north0_m = n;
    g.has_depth_datum = !no_depth;
    const int rows = static_cast<int>((n - s) / g.cell_m) + 1, cols = static_cast<int>((e - w) / g.cell_m) + 1;
    g.height_m.create(rows, cols);
    g.sigma_m.create(rows, cols);
    const LocalXY top{0.5 * (w + e), 0.5 * (s + n)};
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const LocalXY p = g.CellCentre(r, c);
        const double d2 = std::pow(p.east - top.east, 2) + std::pow(p.north - top.north, 2);
        const double h = 0.4 * std::exp(-d2 / 0.8) + 0.05 * std::sin(4 * p.east) * std::cos(3 * p.north);
        const bool hole = p.east < w + 0.3 && p.north < s + 0.3;
        g.height_m(r, c) = hole ? NAN : static_cast<float>(seabed + h);
        g.sigma_m(r, c) = hole ? NAN : static_cast<float>(0.005 + 0.02 * std::sqrt(d2) / 3);
      }
    StoreMissionTerrain(store.get(), t, false);
    double height = 0, sigma = 0;
    if (!g.Sample(top, &height, &sigma)) throw std::runtime_error("the probe is not in the model");
    const HeightDatum datum = UserDatum(g);
    const nlohmann::json relief = *ReadMissionMetadata(*store).relief;
    const LatLon probe = frame.ToLatLon(top);
    nlohmann::json out = {
        {"low_m", relief["low_m"]},
        {"high_m", relief["high_m"]},
        {"datum", datum.name},
        {"probe", {{"lat", probe.lat}, {"lon", probe.lon}, {"height_m", height + datum.offset_m}, {"sigma_m", sigma}}}};
    std::printf("%s\n", out.dump().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "seed_terrain: %s\n", e.what());
    return 1;
  }
}
