// seamap export: copies a map between store kinds (MBTiles <-> folder), with
// its layers, metadata, frames, track and detections; or publishes one of its
// layers as a PMTiles archive or one level as a Cloud-Optimised GeoTIFF.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/export/dem_export.h"
#include "core/export/geotiff_export.h"
#include "core/export/pmtiles_export.h"
#include "core/mission/mission_metadata.h"
#include "core/mission/mission_terrain.h"
#include "core/mission/relief_layer.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap::cli {
namespace {

const char* kHelp =
    "usage: seamap export FROM TO [--overwrite] [--quiet]\n"
    "       seamap export FROM NAME.pmtiles [--layer NAME] [--overwrite] [--quiet]\n"
    "       seamap export FROM NAME.tif [--zoom Z] [--layer NAME] [--resampling AVERAGE]\n"
    "                                   [--threads N] [--overwrite] [--quiet]\n"
    "       seamap export FROM NAME.tif --dem [--overwrite]\n"
    "\n"
    "Copies a map: NAME.mbtiles to a {z}/{x}/{y} folder any static web server can\n"
    "serve, or a folder to MBTiles. Layers, metadata, frames, track and detections\n"
    "come along.\n"
    "\n"
    "TO ending in .pmtiles: a PMTiles v3 archive of the map (or --layer), one file\n"
    "any static host or object store serves to the console's pmtiles.html.\n"
    "TO ending in .tif/.tiff: a Cloud-Optimised GeoTIFF (EPSG:3857, overviews) of\n"
    "zoom --zoom (default: the deepest) for QGIS/GDAL; any zoom, also beyond 22.\n"
    "With --dem: the map's height model (build --terrain) as a float32 GeoTIFF DEM,\n"
    "metres up from the sea surface (else from the survey's mean seabed), nodata\n"
    "-32768, in the mission's local transverse Mercator, with overviews.\n";

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// FROM (or its --layer) as a .pmtiles archive or a GeoTIFF of one level.
int ExportArchive(const TileStore& from, const std::string& source, const std::string& to_path, bool geotiff,
                  const GeotiffOptions& tif, bool quiet) {
  if (geotiff) {
    ProgressBar progress("%", 100, !quiet);
    const GeotiffSummary s =
        ExportGeotiff(from, source, to_path, tif, [&](double f) { progress.Update(static_cast<long>(f * 100)); });
    progress.Finish();
    std::printf("exported zoom %d (%d tiles, %dx%d px, %d bands, EPSG:3857) from %s to %s\n", s.zoom, s.tiles,
                s.width_px, s.height_px, s.bands, source.c_str(), to_path.c_str());
    return 0;
  }
  ProgressBar progress("tiles", static_cast<long>(from.TileCount()), !quiet);
  const PmtilesSummary s =
      ExportPmtiles(from, source, to_path, [&](int64_t done, int64_t) { progress.Update(static_cast<long>(done)); });
  progress.Finish();
  std::printf("exported %llu tiles (%llu stored, zoom %d..%d, %zu leaf directories, %llu bytes) from %s to %s\n",
              static_cast<unsigned long long>(s.addressed_tiles), static_cast<unsigned long long>(s.tile_contents),
              s.min_zoom, s.max_zoom, s.leaf_directories, static_cast<unsigned long long>(s.archive_bytes),
              source.c_str(), to_path.c_str());
  return 0;
}

int64_t CopyTiles(const TileStore& from, TileStore* to, ProgressBar* progress, int64_t* done) {
  int64_t n = 0;
  for (const TileId& id : from.TileIds()) {
    auto bytes = from.GetTile(id);
    if (!bytes) continue;
    to->PutTile(id, *bytes);
    ++n;
    progress->Update(++*done);
  }
  return n;
}

// The map's height model as a GeoTIFF DEM (--dem).
int ExportDemOf(const std::string& from_path, const std::string& to_path, bool overwrite) {
  std::unique_ptr<TileStore> from = OpenExistingMap(from_path, /*writable=*/false);
  const std::optional<MissionTerrain> terrain = ReadMissionTerrain(*from, from_path);
  if (!terrain) throw InputError(from_path, 0, "--dem", "the map has no height model; build it with --terrain");
  std::error_code ec;
  if (std::filesystem::exists(to_path, ec) && !overwrite)
    throw InputError(to_path, 0, "TO", "already exists; use --overwrite to replace it");
  const DemSummary s = ExportDem(*terrain, to_path);
  std::printf(
      "exported the height model (%dx%d cells of %.3g m, %d overviews, heights %.3f..%.3f m from the %s) "
      "from %s to %s\n",
      s.width_px, s.height_px, s.cell_m, s.overviews, s.min_m, s.max_m,
      s.datum == "sea_surface" ? "sea surface" : "mean seabed", from_path.c_str(), to_path.c_str());
  return 0;
}

}  // namespace

int RunExport(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"overwrite", "quiet", "help", "dem"});
  if (args.Flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  const bool overwrite = args.Flag("overwrite"), quiet = args.Flag("quiet");
  if (args.positionals().size() != 2) throw InputError("", 0, "FROM TO", "expected a source map and a destination");
  const std::string from_path = args.positionals()[0], to_path = args.positionals()[1];
  const bool pmtiles = EndsWith(to_path, ".pmtiles");
  const bool geotiff = EndsWith(to_path, ".tif") || EndsWith(to_path, ".tiff");
  if (args.Flag("dem")) {
    if (!geotiff) throw InputError(to_path, 0, "--dem", "a DEM is written as a GeoTIFF: name it NAME.tif");
    args.RejectUnknown();
    return ExportDemOf(from_path, to_path, overwrite);
  }
  GeotiffOptions tif;
  std::optional<std::string> layer;
  if (pmtiles || geotiff) layer = args.Get("layer");
  if (geotiff) {
    tif.zoom = args.GetInt("zoom", -1);
    tif.resampling = args.GetOr("resampling", tif.resampling);
    tif.threads = args.GetInt("threads", 0);
    tif.Check();
  }
  args.RejectUnknown();
  std::unique_ptr<TileStore> from = OpenExistingMap(from_path, /*writable=*/false);
  if (pmtiles || geotiff) {
    std::error_code ec;
    if (std::filesystem::exists(to_path, ec) && !overwrite)
      throw InputError(to_path, 0, "TO", "already exists; use --overwrite to replace it");
    if (!layer) return ExportArchive(*from, from_path, to_path, geotiff, tif, quiet);
    CheckLayerName(*layer);
    const std::vector<std::string> layers = ReadMissionMetadata(*from).ExtraLayers();
    const std::string extra = LayerListText(layers);
    if (std::find(layers.begin(), layers.end(), *layer) == layers.end())
      throw InputError("--layer", 0, "",
                       "'" + *layer + "' is not an extra layer of " + from_path +
                           " (it has: " + (extra.empty() ? "none" : extra) + ")");
    return ExportArchive(*from->OpenLayer(*layer), from_path + " layer " + *layer, to_path, geotiff, tif, quiet);
  }
  const auto metadata = from->Metadata();
  const std::string ext = metadata.count("format") ? metadata.at("format") : "png";
  std::error_code ec;
  if (std::filesystem::exists(to_path, ec) && std::filesystem::equivalent(from_path, to_path, ec))
    throw InputError(to_path, 0, "TO", "is the map being exported; choose another destination");
  if (std::filesystem::exists(to_path, ec) && !std::filesystem::is_empty(to_path, ec)) {
    if (!overwrite) throw InputError(to_path, 0, "TO", "already exists; use --overwrite to replace it");
    RemoveMap(to_path, "TO");
  }
  auto to = OpenTileStore(to_path, ext, /*create=*/true);

  std::vector<std::string> layers = ReadMissionMetadata(metadata).ExtraLayers();
  if (ReadMissionMetadata(metadata).relief) layers.push_back(kReliefLayer);  // the height model's layer
  int64_t total = from->TileCount(), done = 0;
  std::vector<std::unique_ptr<TileStore>> from_layers;
  for (const auto& l : layers) {
    from_layers.push_back(from->OpenLayer(l));
    total += from_layers.back()->TileCount();
  }
  ProgressBar progress("tiles", static_cast<long>(total), !quiet);
  for (const auto& [k, v] : metadata)
    if (k.rfind("layer.", 0) != 0) to->SetMetadata(k, v);
  int64_t copied = CopyTiles(*from, to.get(), &progress, &done);
  for (size_t i = 0; i < layers.size(); ++i) {
    auto to_layer = to->OpenLayer(layers[i]);
    for (const auto& [k, v] : from_layers[i]->Metadata()) to_layer->SetMetadata(k, v);
    copied += CopyTiles(*from_layers[i], to_layer.get(), &progress, &done);
    to_layer->Flush();
  }
  for (const auto& f : from->Records().Frames()) to->Records().PutFrame(f);
  for (const auto& p : from->Records().Track()) to->Records().PutTrackPoint(p);
  // A record a recogniser stored with inf/NaN numbers is left out and said, not a failed export.
  std::vector<int64_t> unreadable;
  for (const auto& d : from->Records().ReadableDetections(&unreadable)) to->Records().PutDetection(d);
  if (!unreadable.empty())
    std::fprintf(stderr,
                 "warning: %s: %zu detections with non-finite or unreadable numbers not exported (first id %lld)\n",
                 from_path.c_str(), unreadable.size(), static_cast<long long>(unreadable[0]));
  if (auto terrain = from->Records().Terrain()) to->Records().PutTerrain(*terrain);
  to->Flush();
  progress.Finish();
  std::printf("exported %lld tiles (%zu layers) from %s to %s\n", static_cast<long long>(copied), layers.size() + 1,
              from_path.c_str(), to_path.c_str());
  return 0;
}

}  // namespace seamap::cli
