// seamap export: copies a map between store kinds (MBTiles <-> folder), with
// its layers, metadata, frames, track and detections; or publishes one of its
// layers as a PMTiles archive or one level as a Cloud-Optimised GeoTIFF.
#include <algorithm>
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/shutdown_signal.h"
#include "core/export/dem_export.h"
#include "core/export/geotiff_export.h"
#include "core/export/pmtiles_export.h"
#include "core/mission/build_state.h"
#include "core/mission/mission_metadata.h"
#include "core/mission/mission_terrain.h"
#include "core/mission/relief_layer.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap::cli {
namespace {

const char* kHelp =
    "usage: seamap export FROM TO [--overwrite] [--partial] [--quiet]\n"
    "       seamap export FROM NAME.pmtiles [--layer NAME] [--overwrite] [--partial] [--quiet]\n"
    "       seamap export FROM NAME.tif [--zoom Z] [--bounds W,S,E,N] [--layer NAME] [--resampling AVERAGE]\n"
    "                                   [--threads N] [--allow-sparse] [--overwrite] [--partial] [--quiet]\n"
    "       seamap export FROM NAME.tif --dem [--overwrite] [--partial]\n"
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
    "-32768, in the mission's local transverse Mercator, with overviews.\n"
    "\n"
    "--bounds W,S,E,N (degrees): only the tiles touching this area go into the GeoTIFF.\n"
    "A GeoTIFF over 64 megapixels that is more than half empty (a frame placed far off)\n"
    "is refused with its size and the main part's bounds; --allow-sparse writes it anyway.\n"
    "A map still being built or interrupted is refused (exit 2); --partial exports what\n"
    "it holds now. Ctrl-C stops an archive export and removes the partial file.\n";

// Ctrl-C or SIGTERM during an archive export: the partial file is removed, exit 130.
struct ExportStopped : std::runtime_error {
  ExportStopped() : std::runtime_error("stopped") {}
};

// A map another process is still building, or whose build was interrupted,
// holds only part of the survey: it is exported only with --partial (with a
// warning naming the state). A replay its operator stopped is a finished map.
void CheckBuildState(const std::string& path, const TileStore& map, bool partial) {
  const MapBuildState state = ReadBuildState(path, map);
  std::string what;
  if (state.state == "building") {
    what = "is still being built";
    if (state.writer_pid && *state.writer_pid > 0)
      what += " (process " + std::to_string(*state.writer_pid) + " is writing it)";
  } else if (state.state == "interrupted") {
    what = "was interrupted: " + state.Explanation();
  } else {
    if (state.state == "stopped")
      std::fprintf(stderr, "seamap export: note: %s was stopped by its operator before the survey ended\n",
                   path.c_str());
    return;
  }
  if (!partial)
    throw InputError(path, 0, "",
                     "the map " + what +
                         "; an export now would hold only part of it. Wait until `seamap info` says complete, "
                         "or pass --partial to export what it holds now");
  std::fprintf(stderr, "seamap export: warning: %s %s; exporting what it holds now (--partial)\n", path.c_str(),
               what.c_str());
}

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// FROM (or its --layer) as a .pmtiles archive or a GeoTIFF of one level.
// `stop` is set by Ctrl-C/SIGTERM: the export throws ExportStopped and leaves no file.
int ExportArchive(const TileStore& from, const std::string& source, const std::string& to_path, bool geotiff,
                  const GeotiffOptions& tif, bool quiet, const std::atomic<bool>& stop) {
  if (geotiff) {
    ProgressBar progress("%", 100, !quiet);
    const GeotiffSummary s = ExportGeotiff(from, source, to_path, tif, [&](double f) {
      if (stop) throw ExportStopped();
      progress.Update(static_cast<long>(f * 100));
    });
    progress.Finish();
    std::printf("exported zoom %d (%d tiles, %dx%d px, %d bands, EPSG:3857) from %s to %s\n", s.zoom, s.tiles,
                s.width_px, s.height_px, s.bands, source.c_str(), to_path.c_str());
    return 0;
  }
  ProgressBar progress("tiles", static_cast<long>(from.TileCount()), !quiet);
  const PmtilesSummary s = ExportPmtiles(from, source, to_path, [&](int64_t done, int64_t) {
    if (stop) throw ExportStopped();
    progress.Update(static_cast<long>(done));
  });
  progress.Finish();
  std::printf("exported %llu tiles (%llu stored, zoom %d..%d, %zu leaf directories, %llu bytes) from %s to %s\n",
              static_cast<unsigned long long>(s.addressed_tiles), static_cast<unsigned long long>(s.tile_contents),
              s.min_zoom, s.max_zoom, s.leaf_directories, static_cast<unsigned long long>(s.archive_bytes),
              source.c_str(), to_path.c_str());
  return 0;
}

// One extra layer of FROM as a .pmtiles archive or a GeoTIFF.
int ExportLayerArchive(TileStore& from, const std::string& from_path, const std::string& layer,
                       const std::string& to_path, bool geotiff, const GeotiffOptions& tif, bool quiet,
                       const std::atomic<bool>& stop) {
  CheckLayerName(layer);
  const std::vector<std::string> layers = ReadMissionMetadata(from).ExtraLayers();
  const std::string extra = LayerListText(layers);
  if (std::find(layers.begin(), layers.end(), layer) == layers.end())
    throw InputError("--layer", 0, "",
                     "'" + layer + "' is not an extra layer of " + from_path +
                         " (it has: " + (extra.empty() ? "none" : extra) + ")");
  return ExportArchive(*from.OpenLayer(layer), from_path + " layer " + layer, to_path, geotiff, tif, quiet, stop);
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
int ExportDemOf(const std::string& from_path, const std::string& to_path, bool overwrite, bool partial) {
  std::unique_ptr<TileStore> from = OpenExistingMap(from_path, /*writable=*/false);
  CheckBuildState(from_path, *from, partial);
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
  Args args(argc, argv, first, {"overwrite", "quiet", "help", "dem", "partial", "allow-sparse"});
  if (args.Flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  const bool overwrite = args.Flag("overwrite"), quiet = args.Flag("quiet"), partial = args.Flag("partial");
  if (args.positionals().size() != 2) throw InputError("", 0, "FROM TO", "expected a source map and a destination");
  const std::string from_path = args.positionals()[0], to_path = args.positionals()[1];
  const bool pmtiles = EndsWith(to_path, ".pmtiles");
  const bool geotiff = EndsWith(to_path, ".tif") || EndsWith(to_path, ".tiff");
  if (args.Flag("dem")) {
    if (!geotiff) throw InputError(to_path, 0, "--dem", "a DEM is written as a GeoTIFF: name it NAME.tif");
    args.RejectUnknown();
    return ExportDemOf(from_path, to_path, overwrite, partial);
  }
  GeotiffOptions tif;
  std::optional<std::string> layer;
  if (pmtiles || geotiff) layer = args.Get("layer");
  if (geotiff) {
    tif.zoom = args.GetInt("zoom", -1);
    tif.resampling = args.GetOr("resampling", tif.resampling);
    tif.threads = args.GetInt("threads", 0);
    if (auto bounds = args.Get("bounds")) tif.bounds = ParseGeotiffBounds(*bounds);
    tif.allow_sparse = args.Flag("allow-sparse");
    tif.Check();
  }
  args.RejectUnknown();
  std::unique_ptr<TileStore> from = OpenExistingMap(from_path, /*writable=*/false);
  CheckBuildState(from_path, *from, partial);
  if (pmtiles || geotiff) {
    std::error_code ec;
    if (std::filesystem::exists(to_path, ec) && !overwrite)
      throw InputError(to_path, 0, "TO", "already exists; use --overwrite to replace it");
    // Ctrl-C/SIGTERM reach a waiting thread (before GDAL starts its own), which asks the export to stop.
    ShutdownSignal shutdown;
    std::atomic<bool> stop{false};
    shutdown.OnSignal([&stop] { stop = true; });
    StopSignalsOnExit stop_signals{shutdown};
    try {
      if (!layer) return ExportArchive(*from, from_path, to_path, geotiff, tif, quiet, stop);
      return ExportLayerArchive(*from, from_path, *layer, to_path, geotiff, tif, quiet, stop);
    } catch (const ExportStopped&) {
      std::fprintf(stderr, "\nseamap export: stopped; the partial %s was removed\n", to_path.c_str());
      return 130;
    }
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
