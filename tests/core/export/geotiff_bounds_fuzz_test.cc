// Randomised --bounds (tests/testing/fuzz.h): hostile numbers and mangled
// text either parse into finite bounds or stop with an InputError naming
// --bounds, quoting at most ~100 characters; random boxes, near the map or
// anywhere on the globe, export the tiles they touch or are refused by name.
// Never a crash, another kind of exception, or a file left behind.
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "core/export/geotiff_export.h"
#include "core/tiles/tile_codec.h"
#include "core/util/error.h"
#include "tests/testing/fuzz.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::Fuzz;
using testing::TempDir;

TEST(GeotiffBoundsFuzz, HostileBoundsTextParsesFiniteOrIsRefusedByName) {
  Fuzz fuzz;
  while (fuzz.More()) {
    std::string text;
    const int parts = static_cast<int>(fuzz.Below(6));
    for (int i = 0; i < parts; ++i) {
      if (i) text += ",";
      text += fuzz.OneIn(3) ? fuzz.HostileNumber() : std::to_string(static_cast<double>(fuzz.Below(400)) - 200.0);
    }
    if (fuzz.OneIn(3)) text = fuzz.Mutate(text);
    if (fuzz.OneIn(20)) text += std::string(fuzz.Below(100000), '9');
    SCOPED_TRACE("case " + std::to_string(fuzz.cases()) + ": '" + text.substr(0, 200) + "'");
    try {
      GeotiffOptions options;
      options.bounds = ParseGeotiffBounds(text);
      EXPECT_TRUE(std::isfinite(options.bounds->west) && std::isfinite(options.bounds->south) &&
                  std::isfinite(options.bounds->east) && std::isfinite(options.bounds->north));
      options.Check();
      EXPECT_LT(options.bounds->west, options.bounds->east);
      EXPECT_LT(options.bounds->south, options.bounds->north);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "--bounds") << e.what();
      EXPECT_LT(std::string(e.what()).size(), 300u) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an InputError: " << e.what();
    }
  }
}

TEST(GeotiffBoundsFuzz, RandomBoxesExportTheTilesTheyTouchOrAreRefused) {
  TempDir dir;
  const std::string map_path = (dir / "m.mbtiles").string();
  const int z = 18, x0 = 229000, y0 = 100000;
  {
    auto store = OpenTileStore(map_path, "png", true);
    const cv::Mat tile(256, 256, CV_8UC2, cv::Scalar(90, 255));
    for (int dy = 0; dy < 3; ++dy)
      for (int dx = 0; dx < 3; ++dx) store->PutTile({z, x0 + dx, y0 + dy}, EncodeTile(tile, {}));
    store->SetMetadata("format", "png");
    store->Flush();
  }
  auto map = OpenExistingMap(map_path, false);
  const LatLonBounds nw = TileBounds({z, x0, y0}), se = TileBounds({z, x0 + 2, y0 + 2});
  const std::string tif = (dir / "out.tif").string();
  Fuzz fuzz;
  while (fuzz.More()) {
    auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * (fuzz.Below(1000001) / 1e6); };
    GeotiffOptions options;
    options.threads = 1;
    if (fuzz.OneIn(4)) {  // anywhere
      const double w = uniform(-180, 179), s = uniform(-85, 84);
      options.bounds = LatLonBounds{w, s, uniform(w, 180), uniform(s, 85.05)};
    } else {  // around the map, a few tiles either side
      const double margin_lon = 3 * (se.east - nw.west), margin_lat = 3 * (nw.north - se.south);
      const double w = uniform(nw.west - margin_lon, se.east + margin_lon);
      const double s = uniform(se.south - margin_lat, nw.north + margin_lat);
      options.bounds = LatLonBounds{w, s, w + uniform(1e-9, margin_lon), s + uniform(1e-9, margin_lat)};
    }
    if (fuzz.OneIn(3)) options.zoom = static_cast<int>(fuzz.Below(22));
    SCOPED_TRACE("case " + std::to_string(fuzz.cases()) + ": bounds " + std::to_string(options.bounds->west) + "," +
                 std::to_string(options.bounds->south) + "," + std::to_string(options.bounds->east) + "," +
                 std::to_string(options.bounds->north) + " zoom " + std::to_string(options.zoom));
    try {
      const GeotiffSummary s = ExportGeotiff(*map, "m.mbtiles", tif, options);
      EXPECT_EQ(s.zoom, z);
      EXPECT_GE(s.tiles, 1);
      EXPECT_LE(s.tiles, 9);
      EXPECT_LE(s.width_px, 3 * 256);
      EXPECT_LE(s.height_px, 3 * 256);
      EXPECT_TRUE(std::filesystem::exists(tif));
      std::filesystem::remove(tif);
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_TRUE(what.rfind("--bounds:", 0) == 0 || what.rfind("--zoom:", 0) == 0) << what;
      EXPECT_FALSE(std::filesystem::exists(tif)) << what;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not an InputError: " << e.what();
    }
  }
}

}  // namespace
}  // namespace seamap
