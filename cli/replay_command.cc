// seamap replay: builds a map while serving it, as if the vehicle were diving
// now: frames of a recorded survey at their recorded pace (or a folder being
// filled, --watch), the server and console live on the growing mission.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "cli/args.h"
#include "cli/build_output.h"
#include "cli/build_setup.h"
#include "cli/commands.h"
#include "cli/detect_setup.h"
#include "cli/georef_overlays.h"
#include "cli/server_setup.h"
#include "cli/shutdown_signal.h"
#include "cli/trajectory_setup.h"
#include "core/detect/detection_record.h"
#include "core/mosaic/mosaic_builder.h"
#include "core/nav/frame_feed.h"
#include "core/tiles/observed_store.h"
#include "core/tiles/tile_version.h"
#include "core/util/error.h"
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
    "  --nav-mode vo|ekf   run the navigation filter online as frames arrive and paint with its pose\n"
    "                      (vo: visual odometry + depth, navigation positions only for the first fix;\n"
    "                      ekf: also the navigation's positions, gated); the mission keeps both tracks\n"
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
      std::ifstream in(survey);
      auto j = nlohmann::json::parse(in);
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

}  // namespace

int RunReplay(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"append", "overwrite", "quiet", "exit-when-done", "detect", "help"});
  if (args.Flag("help")) {
    std::printf("%s%s%s", kHelp, kGeorefOverlayHelp, kServerOptionsHelp);
    return 0;
  }
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
  std::unique_ptr<TrajectoryEstimator> estimator;
  if (auto mode = args.Get("nav-mode")) {
    if (*mode != "nav") {
      const RefineOptions stated = ReadRefineOptions(args, in.config.navigation, in.config.threads);
      estimator = std::make_unique<TrajectoryEstimator>(in.camera, EstimatorOptionsFrom(*mode, stated, "--nav-mode"));
    }
  }
  const GeorefOverlays overlays = ReadGeorefOverlays(args);  // before the map is touched
  const auto detect_model = LiveDetectArgs(args);            // checked before the map is opened
  args.RejectUnknown();

  std::unique_ptr<FrameFeed> feed;
  StopSignalsOnExit stop_signals{shutdown};  // ... and the feed
  if (watch) {
    NavReadOptions nav_options = in.config.nav;
    nav_options.origin = in.frame.origin();
    feed =
        std::make_unique<FolderWatchFeed>(args.GetOr("nav", ""), args.GetOr("images", ""), nav_options, idle_timeout);
  } else {
    feed = std::make_unique<RecordedFeed>(in.frames, speed);
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    feed_ptr = feed.get();
    if (interrupted) feed->Stop();
  }

  // A live map: publish tiles every few frames (a build batches 25 for speed).
  in.config.buffer.batch_frames = std::min(in.config.buffer.batch_frames, 5);
  in.config.buffer.live_tiles = true;
  CheckMemoryFits(in);  // before the map is created
  BuildOutput output = OpenOutput(out, in.config, {append, overwrite, false});
  std::unique_ptr<TileStore>& store = output.store;
  MosaicPlan plan = PlanMosaic(in.config.map, in.camera, in.frame, in.frames.frames, in.channels);
  for (const auto& w : in.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

  server::EventHub events;
  server::MissionState mission;
  overlays.ApplyTo(mission);
  BuildHooks enhance = MakeHooks(in);
  const bool both = in.config.layers == "both" && enhance.preprocess;
  const std::vector<std::string> layers = both ? std::vector<std::string>{"raw", "enhanced"}
                                               : std::vector<std::string>{enhance.preprocess ? "enhanced" : "raw"};
  std::string layer_list;
  for (const auto& l : layers) layer_list += (layer_list.empty() ? "" : ",") + l;
  const std::string format = TileExtension(in.config.map.encoding.format);
  // What a client needs before the first batch lands.
  store->SetMetadata("name", in.config.map.name);
  store->SetMetadata("format", format);
  store->SetMetadata("seamap_layers", layer_list);
  store->SetMetadata("minzoom", std::to_string(plan.min_zoom));
  store->SetMetadata("maxzoom", std::to_string(plan.base_zoom));
  store->SetMetadata("seamap_state", "building");
  if (estimator) store->SetMetadata("seamap_trajectory", nlohmann::json{{"mode", args.GetOr("nav-mode", "")}}.dump());
  store->SetMetadata("seamap_origin", Degrees(in.frame.origin().lat) + "," + Degrees(in.frame.origin().lon));
  store->Flush();

  std::unique_ptr<server::TileSource> tiles;
  ObservedStore observed(store.get(), [&](const std::string& layer, const std::vector<CommittedTile>& done) {
    for (const auto& t : done) {
      if (tiles) tiles->Invalidate(layer, t.id);
      events.Publish(
          "tile",
          nlohmann::json{
              {"layer", layer}, {"z", t.id.z}, {"x", t.id.x}, {"y", t.id.y}, {"version", TileVersionHex(t.version)}}
              .dump());
    }
  });
  tiles = std::make_unique<server::TileSource>(out, 8, 64u << 20, &observed);
  mission.Load(*store);  // an appended mission keeps its frames and track
  mission.SetName(in.config.map.name);
  mission.SetReplay(true);
  mission.SetLayers(layers, format);
  mission.SetOrigin(in.frame.origin().lat, in.frame.origin().lon);
  server::DetectionRegistry detections(&observed, &events);
  detections.Load(*store);

  BuildHooks hooks = both ? BuildHooks{} : enhance;
  hooks.on_frame = [&](const FrameRecord& record, const TrackPoint& point) {
    mission.AddFrame(record, point);
    if (record.status == "used") events.Publish("pose", server::PoseJson(record).dump());
    events.Publish("track", server::TrackPointJson(point).dump());
  };
  if (both) in.config.buffer.memory_cap_mb = std::max(16, in.config.buffer.memory_cap_mb / 2);
  std::unique_ptr<LiveDetector> detector;  // searches the main layer's finished tiles
  LiveDetector::Found publish_found;
  if (detect_model) {
    detector = StartLiveDetector(detect_model, plan, in.config.map.tile_size, in.frame.origin(), store.get(),
                                 in.config.detect, in.config_source);
    hooks.tile_consumers.push_back(detector.get());
    // Live: what is found so far goes through the registry every second (SSE
    // `detection` events: the console shows objects as they are found).
    publish_found = [&detections, model = detector->model()](const std::vector<RecognisedObject>& objects) {
      std::vector<Detection> batch;
      for (const RecognisedObject& o : objects) batch.push_back(ToDetection(o));
      server::PublishOptions options;
      options.model_classes = model.class_names;
      options.replace_model = model.name;
      detections.Publish(std::move(batch), options);
    };
    detector->OnFound(
        publish_found, [&store] { return store->Records().Frames(); }, std::chrono::seconds(1));
  }
  MosaicBuilder builder(in.config, in.camera, in.frame, plan, &observed, hooks);
  std::unique_ptr<TileStore> enhanced_store;
  std::unique_ptr<MosaicBuilder> enhanced;
  if (both) {
    enhanced_store = observed.OpenLayer("enhanced");
    enhanced = std::make_unique<MosaicBuilder>(in.config, in.camera, in.frame, plan, enhanced_store.get(), enhance);
  }

  server::HttpServer http(options, tiles.get(), &mission, &detections, &events);
  http.Bind();
  http.Start();
  const std::string url = ServerUrl(options, http.port());
  std::printf("serving %s (replay of %s at %s -> %s)\n", url.c_str(),
              watch ? watch->c_str() : args.positionals()[0].c_str(),
              speed > 0 ? (std::to_string(speed).substr(0, 4) + "x").c_str() : "full speed", out.c_str());
  std::fflush(stdout);

  const Clock::time_point start = Clock::now();
  Clock::time_point last_progress = start - std::chrono::seconds(1);
  auto publish_progress = [&](const std::string& state, bool force) {
    const auto now = Clock::now();
    if (!force && now - last_progress < std::chrono::milliseconds(500)) return;
    last_progress = now;
    const BuildStats& s = builder.stats();
    server::Progress p;
    p.state = state;
    p.frames_done = s.frames_seen;
    p.frames_total = feed->Total();
    p.frames_rejected = static_cast<int>(s.rejections.size());
    p.tiles_written = s.tiles_written;
    const double seconds = std::chrono::duration<double>(now - start).count();
    p.frames_per_s = seconds > 0 ? s.frames_seen / seconds : 0;
    mission.SetProgress(p);
    events.Publish("progress", mission.StatusJson().dump());
    if (!quiet) {
      std::fprintf(stderr, "\rreplay: %d%s frames, %lld tile writes, %.1f frames/s   ", p.frames_done,
                   p.frames_total ? (" / " + std::to_string(p.frames_total)).c_str() : "",
                   static_cast<long long>(p.tiles_written), p.frames_per_s);
      std::fflush(stderr);
    }
  };
  publish_progress("building", true);

  int exit_code = 0;
  try {
    while (auto item = feed->Next()) {
      if (item->rejection) {
        builder.Reject(*item->rejection);
        if (enhanced) enhanced->Reject(*item->rejection);
      } else {
        FrameSpec frame = *item->frame;
        if (estimator) EstimatePose(estimator.get(), in.camera, &frame);
        builder.Push(frame);
        if (enhanced) enhanced->Push(frame);
      }
      publish_progress("building", false);
    }
    if (enhanced) enhanced->Finish();
    builder.Finish();
    if (detector) FinishLiveDetector(*detector, *store, publish_found);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\nseamap replay: failed: %s\n", e.what());
    exit_code = 1;
  }
  const bool complete = !interrupted && exit_code == 0;
  try {
    if (!complete) store->SetMetadata("seamap_state", "stopped");
    store->Flush();
  } catch (const std::exception& e) {  // e.g. the disk is still full: say so, keep serving what is there
    std::fprintf(stderr, "seamap replay: cannot mark the mission stopped: %s\n", e.what());
    exit_code = 1;
  }
  publish_progress(complete ? "complete" : "stopped", true);
  if (!quiet) std::fprintf(stderr, "\n");
  const BuildStats& s = builder.stats();
  std::printf("replay %s: frames used %d, rejected %zu; %lld tile writes\n", complete ? "complete" : "stopped",
              s.frames_used, s.rejections.size(), static_cast<long long>(s.tiles_written));
  for (const auto& r : s.rejections) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
  std::fflush(stdout);

  if (!exit_when_done && !interrupted) {
    std::printf("still serving %s (Ctrl-C to stop)\n", url.c_str());
    std::fflush(stdout);
    std::unique_lock<std::mutex> lock(mutex);
    woken.wait(lock, [&] { return interrupted.load(); });
  }
  http.Stop();
  if (exit_code == 0 && !complete) exit_code = 130;  // stopped by Ctrl-C before the end
  return exit_code;
}

}  // namespace seamap::cli
