// seamap export: copies a map between store kinds (MBTiles <-> folder), with
// its layers, metadata, frames, track and detections.
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap::cli {
namespace {

const char* kHelp =
    "usage: seamap export FROM TO [--overwrite] [--quiet]\n"
    "\n"
    "Copies a map: NAME.mbtiles to a {z}/{x}/{y} folder any static web server can\n"
    "serve, or a folder to MBTiles. Layers, metadata, frames, track and detections\n"
    "come along.\n";

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

}  // namespace

int RunExport(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"overwrite", "quiet", "help"});
  if (args.Flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  const bool overwrite = args.Flag("overwrite"), quiet = args.Flag("quiet");
  args.RejectUnknown();
  if (args.positionals().size() != 2) throw InputError("", 0, "FROM TO", "expected a source map and a destination");
  const std::string from_path = args.positionals()[0], to_path = args.positionals()[1];
  std::unique_ptr<TileStore> from = OpenExistingMap(from_path, /*writable=*/false);
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

  std::vector<std::string> layers;
  if (metadata.count("seamap_layers")) {
    std::stringstream in(metadata.at("seamap_layers"));
    std::string part;
    std::getline(in, part, ',');  // the first is the main map; the others are layers
    while (std::getline(in, part, ','))
      if (!part.empty()) layers.push_back(part);
  }
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
  for (const auto& f : from->Frames()) to->PutFrame(f);
  for (const auto& p : from->Track()) to->PutTrackPoint(p);
  for (const auto& d : from->Detections()) to->PutDetection(d);
  to->Flush();
  progress.Finish();
  std::printf("exported %lld tiles (%zu layers) from %s to %s\n", static_cast<long long>(copied), layers.size() + 1,
              from_path.c_str(), to_path.c_str());
  return 0;
}

}  // namespace seamap::cli
