// seamap info: what a built map holds.
#include <cstdio>
#include <filesystem>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/mission/build_state.h"
#include "core/mission/mission_metadata.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace fs = std::filesystem;

namespace {
uintmax_t SizeOnDisk(const std::string& path) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) {
    uintmax_t total = fs::file_size(path, ec);
    for (const char* suffix : {"-wal", "-shm"})
      if (fs::exists(path + suffix, ec)) total += fs::file_size(path + suffix, ec);
    return total;
  }
  uintmax_t total = 0;
  for (auto it = fs::recursive_directory_iterator(path, ec); it != fs::recursive_directory_iterator(); ++it)
    if (it->is_regular_file(ec)) total += it->file_size(ec);
  return total;
}
}  // namespace

int RunInfo(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help"});
  if (args.Flag("help") || args.positionals().size() != 1) {
    std::fputs("usage: seamap info MAP   (a .mbtiles file or a tile folder)\n", args.Flag("help") ? stdout : stderr);
    return args.Flag("help") ? 0 : 2;
  }
  args.RejectUnknown();
  const std::string path = args.positionals()[0];
  std::error_code ec;
  if (!fs::exists(path, ec)) throw InputError(path, 0, "", "no such map");
  auto store = OpenTileStore(path, "png", /*create=*/false);
  auto meta = store->Metadata();
  auto get = [&](const std::string& k) { return meta.count(k) ? meta[k] : std::string("-"); };
  const MissionMetadata mission = ReadMissionMetadata(meta);
  const std::string tile_size = mission.tile_size_px ? std::to_string(*mission.tile_size_px) : "-";
  auto frames = store->Records().Frames();
  size_t used = 0, corrected = 0;
  for (const auto& f : frames) {
    used += f.status == "used";
    corrected += f.nav.has_value();
  }
  std::printf("map:       %s\n", path.c_str());
  std::printf("name:      %s\n", get("name").c_str());
  std::printf("format:    %s, %s px tiles\n", get("format").c_str(), tile_size.c_str());
  std::printf("zooms:     %s..%s\n", get("minzoom").c_str(), get("maxzoom").c_str());
  std::printf("bounds:    %s (w,s,e,n)\n", get("bounds").c_str());
  std::printf("center:    %s\n", get("center").c_str());
  std::printf("tiles:     %lld\n", static_cast<long long>(store->TileCount()));
  std::printf("frames:    %zu (%zu used, %zu rejected)\n", frames.size(), used, frames.size() - used);
  std::printf("track:     %zu points\n", store->Records().Track().size());
  if (corrected)
    std::printf("nav:       trajectory corrected in %zu of %zu frames (the navigation's poses kept)\n", corrected,
                frames.size());
  else
    std::printf("nav:       trajectory not corrected (frames placed at the navigation's poses)\n");
  if (mission.trajectory && mission.trajectory->contains("flagged_frames")) {
    std::string text;  // frames the refinement could not use, by why (their names: the map's seamap_trajectory)
    for (const auto& [why, entry] : (*mission.trajectory)["flagged_frames"].items())
      if (entry.is_object() && entry.value("frames", 0) > 0)
        text += (text.empty() ? "" : ", ") + why + " " + std::to_string(entry.value("frames", 0));
    if (!text.empty()) std::printf("flagged:   %s\n", text.c_str());
  }
  const MapBuildState state = ReadBuildState(path, *store);
  std::string state_text = state.state.empty() ? "-" : state.state;
  if (state.state == "building" && state.writer_pid)
    state_text += *state.writer_pid > 0 ? " (process " + std::to_string(*state.writer_pid) + " is writing it)"
                                        : " (another process is writing it)";
  if (state.state == "interrupted") state_text += ": " + state.Explanation();
  std::printf("state:     %s\n", state_text.c_str());
  std::printf("layers:    %s\n", mission.layers ? LayerListText(*mission.layers).c_str() : "-");
  if (mission.relief)  // a map built with --terrain
    std::printf("terrain:   height model, relief layer %.2f..%.2f m (%s); export it with --dem\n",
                mission.relief->value("low_m", 0.0), mission.relief->value("high_m", 0.0),
                mission.relief->value("datum", "").c_str());
  std::printf("size:      %.1f MiB\n", SizeOnDisk(path) / 1048576.0);
  return 0;
}

}  // namespace seamap::cli
