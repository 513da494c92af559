// seamap serve: a built map (MBTiles or folder) over HTTP with the console.
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <mutex>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/georef_overlays.h"
#include "cli/server_setup.h"
#include "cli/shutdown_signal.h"
#include "core/georef/georef_inputs.h"
#include "core/mission/build_state.h"
#include "core/mission/mission_metadata.h"
#include "core/mosaic/build_config.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"
#include "server/http_server.h"

namespace seamap::cli {
namespace fs = std::filesystem;
namespace {

const char* kHelp =
    "usage: seamap serve MAP [options]\n"
    "       seamap serve FOLDER [options]\n"
    "\n"
    "Serves a map built by `seamap build` (NAME.mbtiles or a tile folder): tiles,\n"
    "TileJSON, the REST API, live events and the operator console.\n"
    "A FOLDER of maps (every .mbtiles and tile folder in it) is served read-only\n"
    "as a catalogue: GET /api/missions, each under /missions/{id}/tiles.json.\n"
    "\n"
    "  --config FILE       settings; its \"server\" object gives host, port, token, threads\n"
    "  --images DIR        where the original photos are when their recorded paths are gone\n"
    "  --read-only         never write to the map (operator marks are refused)\n";

// The map opened for writing operator marks; null when it cannot be.
std::unique_ptr<TileStore> OpenForMarks(const std::string& path) {
  try {
    return OpenExistingMap(path, /*writable=*/true);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "warning: %s: cannot open for writing (%s); operator marks are refused\n", path.c_str(),
                 e.what());
    return nullptr;
  }
}

// Serves until Ctrl-C or SIGTERM, following every two seconds the maps
// another process is writing (server::HttpServer::Follow). `started` runs
// once the server answers (it tells the operator where to look).
void ServeUntilStopped(server::HttpServer& http, ShutdownSignal& shutdown, const std::function<void()>& started) {
  std::mutex mutex;
  std::condition_variable stopped;
  bool stop = false;
  StopSignalsOnExit stop_signals{shutdown};  // the callback uses the three above
  shutdown.OnSignal([&] {
    std::lock_guard<std::mutex> lock(mutex);
    stop = true;
    stopped.notify_all();
  });
  http.Start();
  started();
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (!stopped.wait_for(lock, std::chrono::seconds(2), [&] { return stop; })) {
      lock.unlock();
      http.Follow();
      lock.lock();
    }
  }
  std::fprintf(stderr, "seamap serve: stopping\n");
  http.Stop();
}

// `seamap serve FOLDER`: the catalogue until Ctrl-C.
int ServeCatalogue(const std::string& folder, const server::ServerOptions& options, ShutdownSignal& shutdown) {
  server::HttpServer http(options, folder);
  http.Bind();
  ServeUntilStopped(http, shutdown, [&] {
    const auto missions = http.Missions();
    size_t available = 0;
    for (const auto& m : missions) {
      available += m.available;
      if (!m.available) std::fprintf(stderr, "warning: %s is unavailable: %s\n", m.path.c_str(), m.reason.c_str());
    }
    std::printf("serving %s (catalogue of %s: %zu missions, %zu available)\n", ServerUrl(options, http.port()).c_str(),
                folder.c_str(), missions.size(), available);
    std::fflush(stdout);
  });
  return 0;
}

}  // namespace

int RunServe(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"read-only", "help"});
  if (args.Flag("help")) {
    std::printf("%s%s%s", kHelp, kGeorefOverlayHelp, kServerOptionsHelp);
    return 0;
  }
  if (args.positionals().size() != 1)
    throw InputError("", 0, "MAP", "expected exactly one map to serve (NAME.mbtiles or a tile folder)");
  const std::string path = args.positionals()[0];
  BuildConfig config;
  const std::optional<std::string> config_path = args.Get("config");
  if (config_path) config = LoadBuildConfig(*config_path);
  server::ServerOptions options = ReadServerOptions(args, config.server, config_path.value_or(""));
  if (auto images = args.Get("images")) options.photo_dir = *images;
  const bool read_only = args.Flag("read-only");
  const GeorefOverlays overlays = ReadGeorefOverlays(args);  // before serving: bad input stops here
  args.RejectUnknown();

  ShutdownSignal shutdown;  // before any thread starts
  const bool mbtiles = IsMBTilesPath(path);
  std::error_code ec;
  if (!mbtiles && fs::is_directory(path, ec) && !fs::exists(fs::path(path) / "metadata.json", ec)) {
    if (overlays.any())
      throw InputError(path, 0, overlays.buoy_file ? "--buoy" : "--georef-nav",
                       "goes with one map, not a folder of maps");
    return ServeCatalogue(path, options, shutdown);
  }
  if (mbtiles ? !fs::is_regular_file(path, ec) : !fs::is_regular_file(fs::path(path) / "metadata.json", ec))
    throw InputError(
        path, 0, "MAP",
        mbtiles ? "no such MBTiles file" : "is not a tile folder (no metadata.json); build one with seamap build");

  server::EventHub events;
  server::TileSource tiles(path, 8);
  std::unique_ptr<TileStore> writer = read_only ? nullptr : OpenForMarks(path);
  std::unique_ptr<TileStore> reader = writer ? nullptr : OpenExistingMap(path, /*writable=*/false);
  const TileStore& records = writer ? *writer : *reader;

  server::MissionState mission;
  mission.Load(records);
  mission.SetLayers(tiles.Layers(), tiles.Format());
  overlays.ApplyTo(mission);
  server::DetectionRegistry detections(writer.get(), &events);
  detections.Load(records);

  server::HttpServer http(options, &tiles, &mission, &detections, &events);
  // The state as recorded, a build still running (it holds MAP.lock) or
  // interrupted: the server says which, and how an interrupted one goes on.
  // A map another process is still building is followed (frames, track,
  // state), and detections another process adds to any map, too.
  http.FollowMap(path, records);
  http.Bind();
  ServeUntilStopped(http, shutdown, [&] {
    std::printf("serving %s (%s, %zu frames, %zu track points)\n", ServerUrl(options, http.port()).c_str(),
                path.c_str(), static_cast<size_t>(mission.progress().frames_done),
                static_cast<size_t>(mission.TrackSize()));
    std::fflush(stdout);
  });
  if (writer) writer->Flush();
  return 0;
}

}  // namespace seamap::cli
