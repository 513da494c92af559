// seamap replay: builds a map while serving it, as if the vehicle were diving
// now: frames of a recorded survey at their recorded pace (or a folder being
// filled, --watch), the server and console live on the growing mission.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "cli/args.h"
#include "cli/build_setup.h"
#include "cli/commands.h"
#include "cli/detect_setup.h"
#include "cli/georef_overlays.h"
#include "cli/server_setup.h"
#include "cli/shutdown_signal.h"
#include "cli/stereo_setup.h"
#include "cli/trajectory_setup.h"
#include "core/controllers/live_stereo.h"
#include "core/controllers/mission_build.h"
#include "core/detect/detection_record.h"
#include "core/nav/frame_feed.h"
#include "core/tiles/tile_codec.h"
#include "core/tiles/tile_version.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "server/http_server.h"

namespace seamap::cli {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
namespace {

const char* kHelp =
    "usage: seamap replay SURVEY --out MAP [options]\n"
    "       seamap replay --watch DIR --out MAP [options]\n"
    "\n"
    "Builds MAP while serving it: SURVEY is a folder as `seamap simulate` writes it\n"
    "(photo/, nav.csv, camera.json, survey.json), played at its recorded pace.\n"
    "With --watch, frames are taken as photos and navigation lines appear in DIR.\n"
    "Takes every `seamap build` option (--images, --nav, --camera, --origin default\n"
    "to the survey's own; --config, --tile-format, --enhance, ...).\n"
    "\n"
    "  --speed X           X times the recorded pace (default 1); 0 or max: as fast as possible\n"
    "  --out MAP           NAME.mbtiles or a folder; --append / --overwrite as for build\n"
    "  --watch DIR         take frames from a folder being filled (nav.csv + photo/)\n"
    "  --idle-timeout S    with --watch: finish after S seconds without a new frame (default: Ctrl-C)\n"
    "  --exit-when-done    stop serving when the replay ends (default: keep serving until Ctrl-C)\n"
    "  --terrain           estimate the seabed's shape from the photos at the end of the dive (after the\n"
    "                      final refinement with --refine-nav) and paint the map again onto it, as build\n"
    "                      --terrain paints it (takes build's --max-relief, --dem-cell, --dem-max-sigma, ...)\n"
    "  --terrain-file DEM  paint a true orthophoto onto this height model (as build --terrain-file)\n"
    "  --nav-mode vo|ekf   run the navigation filter online as frames arrive and paint with its pose\n"
    "                      (vo: visual odometry + depth, navigation positions only for the first fix;\n"
    "                      ekf: also the navigation's positions, gated); the mission keeps both tracks\n"
    "  --refine-nav        refine the navigation from the photos as frames arrive (a worker registers them\n"
    "                      across passes and loops) and paint again what moved; at the end the whole dive\n"
    "                      is refined as build --refine-nav refines it and the map painted again (takes\n"
    "                      build's --nav-noise, --nav-drift, --heading-noise, --refine-method, ...)\n"
    "  --refine-features-mb N  with --refine-nav: the worker keeps at most N MB of features (default 512,\n"
    "                      about 2,000 frames; 0: no bound); a later pass over frames whose features were\n"
    "                      freed extracts them again from the photos\n"
    "  --trajectory-out F  at the end, write the trajectory the frames were placed with (the filter's with\n"
    "                      --nav-mode) to F, in seamap trajectory's CSV form\n"
    "  --detect            search tiles for objects as they are finished (--detect-model FILE: its\n"
    "                      ONNX model, default data/models/seabed_objects.onnx)\n"
    "  --quiet             no progress line\n";

// Degrees with every digit that matters (std::to_string keeps six decimals: 5 cm).
std::string Degrees(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10f", v);
  return buf;
}

// Survey folder defaults for the build options a survey folder answers.
void SurveyDefaults(Args& args, const fs::path& dir) {
  std::error_code ec;
  args.SetDefault("images", (fs::is_directory(dir / "photo", ec) ? dir / "photo" : dir).string());
  args.SetDefault("nav", (dir / "nav.csv").string());
  args.SetDefault("camera", (dir / "camera.json").string());
  const fs::path survey = dir / "survey.json";
  if (fs::is_regular_file(survey, ec)) {
    try {
      const auto j = ReadJsonFile(survey.string(), "survey description");
      if (j.contains("origin") && j["origin"].is_array() && j["origin"].size() == 2)
        args.SetDefault("origin", Degrees(j["origin"][0].get<double>()) + "," + Degrees(j["origin"][1].get<double>()));
    } catch (const nlohmann::json::exception& e) {
      throw InputError(survey.string(), 0, "origin", std::string("cannot read the survey description: ") + e.what());
    }
  }
}

double ParseSpeed(const std::string& text) {
  if (text == "max") return 0;
  try {
    size_t used = 0;
    double v = std::stod(text, &used);
    if (used == text.size() && v >= 0) return v;
  } catch (const std::exception&) {
  }
  throw InputError("", 0, "--speed", "expected a factor >= 0 (or max), got '" + text + "'");
}

// Waits for a watched folder's navigation to have a first complete line and
// for a first photo to be complete (gray or colour is decided from it).
void WaitForFirstFrame(const std::string& nav, const std::string& images, const std::atomic<bool>& stop) {
  bool told = false;
  std::map<std::string, uintmax_t> sizes;
  while (!stop) {
    std::ifstream in(nav);
    std::string line;
    int complete = 0;
    while (std::getline(in, line) && complete < 2)
      if (!in.eof()) ++complete;
    bool photo = false;
    std::error_code ec;
    if (complete >= 2 && fs::is_directory(images, ec)) {
      for (const auto& entry : fs::directory_iterator(images, ec)) {
        static const std::set<std::string> kImages = {".png",  ".jpg", ".jpeg", ".tif",
                                                      ".tiff", ".bmp", ".webp", ".pgm"};
        std::string ext = entry.path().extension().string();
        for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (!entry.is_regular_file(ec) || !kImages.count(ext)) continue;
        const uintmax_t size = entry.file_size(ec);
        auto previous = sizes.find(entry.path().string());
        if (size > 0 && previous != sizes.end() && previous->second == size) photo = true;
        sizes[entry.path().string()] = size;
      }
    }
    if (photo) return;  // header, one record, one photo that stopped growing
    if (!told)
      std::fprintf(stderr, "seamap replay: waiting for navigation in %s and photos in %s\n", nav.c_str(),
                   images.c_str());
    told = true;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

// SURVEY or --watch DIR, whose files are the build options' defaults; returns --watch's folder.
std::optional<std::string> ReadSurveyFolder(Args& args) {
  const std::optional<std::string> watch = args.Get("watch");
  if (watch) {
    if (!args.positionals().empty()) throw InputError("", 0, "--watch", "takes the folder; give no SURVEY as well");
    SurveyDefaults(args, *watch);
  } else {
    if (args.positionals().size() != 1)
      throw InputError("", 0, "SURVEY", "expected one survey folder (photo/, nav.csv, camera.json) or --watch DIR");
    if (!fs::is_directory(args.positionals()[0]))
      throw InputError(args.positionals()[0], 0, "SURVEY", "is not a folder");
    SurveyDefaults(args, args.positionals()[0]);
  }
  return watch;
}

// --nav-mode vo|ekf: the navigation filter online (nav, or none: the navigation as given).
PoseSourceOptions ReadNavMode(Args& args, const BuildInputs& in) {
  PoseSourceOptions poses;
  poses.max_image_pixels = in.config.frames.max_image_pixels;  // guards the filter's reads too
  if (auto mode = args.Get("nav-mode"); mode && *mode != "nav") {
    poses.mode = PoseMode::kFilter;
    poses.filter =
        EstimatorOptionsFrom(*mode, ReadRefineOptions(args, in.config.navigation, in.config.threads), "--nav-mode");
  }
  return poses;
}

// --refine-nav (or the config's navigation.refine): refinement as frames
// arrive, with build --refine-nav's options; whether it was asked for.
bool ReadLiveRefine(Args& args, const BuildInputs& in, PoseSourceOptions* poses) {
  const bool refine = args.Flag("refine-nav") || in.config.navigation.refine;
  poses->refine = ReadRefineOptions(args, in.config.navigation, in.config.threads);
  poses->feature_enhance = ReadFeatureEnhance(args);
  return refine;
}

// The feed of frames: the recorded survey at its pace, or the watched folder.
std::unique_ptr<FrameFeed> OpenFeed(const std::optional<std::string>& watch, Args& args, const BuildInputs& in,
                                    double speed, double idle_timeout) {
  if (!watch) return std::make_unique<RecordedFeed>(in.frames, speed);
  NavReadOptions nav_options = in.config.nav;
  nav_options.origin = in.frame.origin();
  return std::make_unique<FolderWatchFeed>(args.GetOr("nav", ""), args.GetOr("images", ""), nav_options, idle_timeout);
}

// The server's side of a replay: the mission's state, events, tiles and
// detections, fed by the controller's hooks (MissionObserver).
class LiveMission {
 public:
  LiveMission(bool quiet, const FrameFeed* feed) : quiet_(quiet), feed_(feed) {}

  MissionObserver Observer(const std::shared_ptr<const YoloModelInfo>& detect_model) {
    MissionObserver o;
    o.on_tiles_committed = [this](const std::string& layer, const std::vector<CommittedTile>& done) {
      for (const auto& t : done) {
        if (tiles) tiles->Invalidate(layer, t.id);
        events.Publish(
            "tile",
            nlohmann::json{
                {"layer", layer}, {"z", t.id.z}, {"x", t.id.x}, {"y", t.id.y}, {"version", TileVersionHex(t.version)}}
                .dump());
      }
    };
    o.on_frame_placed = [this](const FrameRecord& record, const TrackPoint& point) {
      mission.AddFrame(record, point);
      if (record.status == "used") events.Publish("pose", server::PoseJson(record).dump());
      events.Publish("track", server::TrackPointJson(point).dump());
    };
    o.on_progress = [this](const BuildStats& s) { PublishProgress(s, "building", false); };
    // replay --refine-nav: the console reloads the tracks (the repainted tiles came as `tile` events).
    o.on_trajectory_corrected = [this](int frames, bool final) {
      events.Publish("trajectory", nlohmann::json{{"frames_corrected", frames}, {"final", final}}.dump());
    };
    if (detect_model)  // what is found so far goes through the registry (SSE `detection` events)
      o.on_objects_found = [this, model = detect_model](const std::vector<RecognisedObject>& objects) {
        std::vector<Detection> batch;
        for (const RecognisedObject& obj : objects) batch.push_back(ToDetection(obj));
        server::PublishOptions options;
        options.model_classes = model->class_names;
        options.replace_model = model->name;
        detections->Publish(std::move(batch), options);
      };
    return o;
  }

  // Once the map is open, before its layers are built.
  void Attach(const MissionBuild& build, const GeorefOverlays& overlays) {
    const MissionBuildOptions& o = build.options();
    overlays.ApplyTo(mission);
    tiles = std::make_unique<server::TileSource>(o.out, 8, 64u << 20, build.store());
    mission.Load(*build.store());  // an appended mission keeps its frames and track
    mission.SetName(o.config.map.name);
    mission.SetReplay(true);
    mission.SetLayers(build.layers(), TileExtension(o.config.map.encoding.format));
    mission.SetOrigin(o.frame.origin().lat, o.frame.origin().lon);
    detections = std::make_unique<server::DetectionRegistry>(build.store(), &events);
    detections->Load(*build.store());
  }

  // The mission's progress to the server and, unless quiet, to stderr; at
  // most every half second unless forced.
  void PublishProgress(const BuildStats& s, const std::string& state, bool force) {
    const auto now = Clock::now();
    if (!force && now - last_progress_ < std::chrono::milliseconds(500)) return;
    last_progress_ = now;
    server::Progress p;
    p.state = state;
    p.frames_done = s.frames_seen;
    p.frames_total = feed_->Total();
    p.frames_rejected = static_cast<int>(s.rejections.size());
    p.tiles_written = s.tiles_written;
    const double seconds = std::chrono::duration<double>(now - start_).count();
    p.frames_per_s = seconds > 0 ? s.frames_seen / seconds : 0;
    mission.SetProgress(p);
    events.Publish("progress", mission.StatusJson().dump());
    if (!quiet_) {
      std::string lag;  // replay --refine-nav: how far the refinement is behind the frames
      if (const auto l = refine_lag ? refine_lag() : std::nullopt)
        lag = ", refine " + std::to_string(l->frames_behind) + " frames behind (" +
              std::to_string(l->seconds_behind).substr(0, 4) + " s)";
      std::fprintf(stderr, "\rreplay: %d%s frames, %lld tile writes, %.1f frames/s%s   ", p.frames_done,
                   p.frames_total ? (" / " + std::to_string(p.frames_total)).c_str() : "",
                   static_cast<long long>(p.tiles_written), p.frames_per_s, lag.c_str());
      std::fflush(stderr);
    }
  }
  // From now on frames per second count (the server is up).
  void StartClock() { start_ = Clock::now(), last_progress_ = start_ - std::chrono::seconds(1); }

  server::EventHub events;
  server::MissionState mission;
  std::function<std::optional<LiveRefinerLag>()> refine_lag;  // replay --refine-nav
  std::unique_ptr<server::TileSource> tiles;
  std::unique_ptr<server::DetectionRegistry> detections;

 private:
  bool quiet_;
  const FrameFeed* feed_;
  Clock::time_point start_ = Clock::now(), last_progress_ = start_ - std::chrono::seconds(1);
};

// replay --refine-nav: what the live refinement did, and how far behind the frames it ran.
void PrintRefineLag(const MissionBuild& build) {
  const auto lag = build.refine_lag();
  if (!lag) return;
  std::printf(
      "refine live: %d solves, %d cross-pass pairs, %d frames painted again; lag at most %.1f s, %d frames left to "
      "the final solve; features at most %.0f MB (%d frames freed, %d extracted again)\n",
      lag->solves, lag->cross_pairs, lag->frames_repainted, lag->worst_seconds, lag->frames_behind,
      lag->peak_feature_mb, lag->features_freed, lag->features_again);
}

// Runs the feed through the build; its end (complete, stopped, failed) told
// to the map, the server and the terminal. Returns the exit code so far.
int ReplayFeed(MissionBuild& build, FrameFeed& feed, LiveMission& live, bool quiet,
               const std::atomic<bool>& interrupted) {
  live.StartClock();
  live.PublishProgress(build.stats(), "building", true);
  int exit_code = 0;
  try {
    build.Run(feed);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\nseamap replay: failed: %s\n", e.what());
    exit_code = 1;
  }
  const bool complete = !interrupted && exit_code == 0;
  try {
    build.Conclude(complete);
  } catch (const std::exception& e) {  // e.g. the disk is still full: say so, keep serving what is there
    std::fprintf(stderr, "seamap replay: cannot mark the mission stopped: %s\n", e.what());
    exit_code = 1;
  }
  live.mission.LoadTerrain(*build.store());  // a height model the build stored (--terrain): /api/terrain answers
  // --refine-nav, --terrain: the records of the final repaint (and the refined report) replace those served.
  if (build.refine_lag() || build.options().config.terrain.estimate) live.mission.Load(*build.store());
  live.PublishProgress(build.stats(), complete ? "complete" : "stopped", true);
  if (!quiet) std::fprintf(stderr, "\n");
  const BuildStats& s = build.stats();
  std::printf("replay %s: frames used %d, rejected %zu; %lld tile writes\n", complete ? "complete" : "stopped",
              s.frames_used, s.rejections.size(), static_cast<long long>(s.tiles_written));
  PrintRefineLag(build);
  for (const auto& r : s.rejections) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
  std::fflush(stdout);
  if (exit_code == 0 && !complete) exit_code = 130;  // stopped by Ctrl-C before the end
  return exit_code;
}

// --stereo: the frames placed feed the pairs' poses; the pairs still due are
// located once the layers are finished, before the mission is concluded.
void HookUpLiveStereo(LiveStereo* stereo, MissionObserver* observer) {
  if (!stereo) return;
  observer->on_frame_placed = [stereo, placed = observer->on_frame_placed](const FrameRecord& record,
                                                                           const TrackPoint& point) {
    if (placed) placed(record, point);
    stereo->OnFramePlaced(record);
  };
  observer->on_layers_finished = [stereo, finished = observer->on_layers_finished] {
    if (finished) finished();
    stereo->Finish();
  };
}

// The located objects to the console (SSE `detection` events) and the mission, as they are found.
void StartLiveStereo(LiveStereo* stereo, const MissionBuild& build, LiveMission& live) {
  if (!stereo) return;
  stereo->Start(build.options().frame, [stereo, &live](std::vector<Detection> objects) {
    server::PublishOptions options;
    options.model_classes = {stereo->model_name()};
    options.replace_model = stereo->model_file();  // this model's earlier unreviewed locations are replaced
    live.detections->Publish(std::move(objects), options);
  });
}

// What stereo found in the dive, a line per pair and the count.
void PrintLiveStereo(LiveStereo* stereo) {
  if (!stereo) return;
  const LiveStereoSummary summary = stereo->Finish();
  for (const std::string& line : summary.lines) std::printf("stereo %s\n", line.c_str());
  std::printf("stereo: %d pairs: %d found, %d not found, %d outside the frames' times\n", summary.pairs, summary.found,
              summary.not_found, summary.skipped);
}

}  // namespace

int RunReplay(int argc, char** argv, int first) {
  Args args(argc, argv, first,
            {"append", "overwrite", "quiet", "exit-when-done", "detect", "refine-nav", "terrain", "terrain-from-bundle",
             "help"});
  if (args.Flag("help")) {
    std::printf("%s%s%s%s", kHelp, kLiveStereoHelp, kGeorefOverlayHelp, kServerOptionsHelp);
    return 0;
  }
  const std::optional<std::string> watch = ReadSurveyFolder(args);
  const double speed = ParseSpeed(args.GetOr("speed", "1"));
  const double idle_timeout = args.GetDouble("idle-timeout", 0);
  const bool exit_when_done = args.Flag("exit-when-done"), quiet = args.Flag("quiet");
  const bool append = args.Flag("append"), overwrite = args.Flag("overwrite");
  const std::string out = args.Require("out");

  ShutdownSignal shutdown;  // before any thread starts
  std::atomic<bool> interrupted{false};
  std::mutex mutex;
  std::condition_variable woken;
  FrameFeed* feed_ptr = nullptr;
  StopSignalsOnExit stop_signals_first{shutdown};  // the callback below uses these locals
  shutdown.OnSignal([&] {
    std::lock_guard<std::mutex> lock(mutex);
    interrupted = true;
    if (feed_ptr) feed_ptr->Stop();
    woken.notify_all();
  });
  if (watch) WaitForFirstFrame(args.GetOr("nav", ""), args.GetOr("images", ""), interrupted);
  if (interrupted) return 130;

  BuildInputs in = ReadBuildInputs(args);
  server::ServerOptions options = ReadServerOptions(args, in.config.server, in.config_source);
  options.photo_dir = args.GetOr("images", "");
  PoseSourceOptions poses = ReadNavMode(args, in);
  const bool refine_live = ReadLiveRefine(args, in, &poses);
  const double refine_features_mb = args.GetDouble("refine-features-mb", 512);
  if (!(refine_features_mb >= 0 && refine_features_mb <= 1e6))
    throw InputError("", 0, "--refine-features-mb", "expected megabytes >= 0 (0: no bound)");
  ReadTerrainOptions(args, &in.config.terrain);              // --terrain: estimated at the end of the dive
  const GeorefOverlays overlays = ReadGeorefOverlays(args);  // before the map is touched
  const auto detect_model = LiveDetectArgs(args);            // checked before the map is opened
  const std::optional<std::string> trajectory_out = args.Get("trajectory-out");
  if (trajectory_out) CheckTrajectoryOut(*trajectory_out);
  const std::shared_ptr<const StereoLocateOptions> stereo_options = ReadLiveStereo(args);
  args.RejectUnknown();
  // The rig, model and pairs' times read before the map is touched.
  const std::unique_ptr<LiveStereo> stereo = stereo_options ? std::make_unique<LiveStereo>(*stereo_options) : nullptr;

  std::unique_ptr<FrameFeed> feed = OpenFeed(watch, args, in, speed, idle_timeout);
  StopSignalsOnExit stop_signals{shutdown};  // ... and the feed
  {
    std::lock_guard<std::mutex> lock(mutex);
    feed_ptr = feed.get();
    if (interrupted) feed->Stop();
  }
  const std::vector<std::string> warnings = in.warnings;
  MissionBuildOptions build_options = MissionOptions(std::move(in));
  build_options.out = out;
  build_options.append = append, build_options.overwrite = overwrite;
  build_options.live = true;
  build_options.poses = poses;
  build_options.poses.quiet = build_options.poses.quiet || quiet;  // the final refinement's progress bars too
  build_options.refine_live = refine_live;
  build_options.refine_live_feature_bytes = static_cast<size_t>(refine_features_mb * (1 << 20));
  HookUpDetector(detect_model, &build_options);
  LiveMission live(quiet, feed.get());
  MissionObserver observer = live.Observer(detect_model);
  HookUpLiveStereo(stereo.get(), &observer);
  MissionBuild build(std::move(build_options), std::move(observer));
  live.refine_lag = [&build] { return build.refine_lag(); };
  build.Open();
  for (const auto& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  live.Attach(build, overlays);
  StartLiveStereo(stereo.get(), build, live);
  build.Start();

  server::HttpServer http(options, live.tiles.get(), &live.mission, live.detections.get(), &live.events);
  http.Bind();
  http.Start();
  const std::string url = ServerUrl(options, http.port());
  std::printf("serving %s (replay of %s at %s -> %s)\n", url.c_str(),
              watch ? watch->c_str() : args.positionals()[0].c_str(),
              speed > 0 ? (std::to_string(speed).substr(0, 4) + "x").c_str() : "full speed", out.c_str());
  std::fflush(stdout);

  int exit_code = ReplayFeed(build, *feed, live, quiet, interrupted);
  PrintLiveStereo(stereo.get());
  if (trajectory_out) {  // what the frames were placed with, stopped or not
    try {
      WriteTrajectoryOut(*build.store(), *trajectory_out);
    } catch (const InputError& e) {
      std::fprintf(stderr, "seamap replay: %s\n", e.what());
      if (exit_code == 0) exit_code = 2;
    }
  }
  if (!exit_when_done && !interrupted) {
    std::printf("still serving %s (Ctrl-C to stop)\n", url.c_str());
    std::fflush(stdout);
    std::unique_lock<std::mutex> lock(mutex);
    woken.wait(lock, [&] { return interrupted.load(); });
  }
  http.Stop();
  return exit_code;
}

}  // namespace seamap::cli
