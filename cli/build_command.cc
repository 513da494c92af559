// seamap build: photos + navigation + camera -> tile pyramid.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "cli/args.h"
#include "cli/build_output.h"
#include "cli/build_setup.h"
#include "cli/commands.h"
#include "cli/detect_setup.h"
#include "cli/trajectory_setup.h"
#include "core/mosaic/mosaic_builder.h"
#include "core/util/error.h"
#include "core/util/process_stats.h"
#include "core/util/progress.h"

namespace seamap::cli {
namespace {

const char* kHelp =
    "usage: seamap build --images DIR --nav FILE --camera FILE --out PATH [options]\n"
    "\n"
    "  --images DIR        folder with the photos named in the navigation\n"
    "  --nav FILE          navigation CSV (or the seed paper's text format)\n"
    "  --camera FILE       camera model: JSON, or OpenCV calibration YAML/XML\n"
    "  --out PATH          NAME.mbtiles (one-file mission) or a folder for {z}/{x}/{y} tiles\n"
    "  --origin LAT,LON    origin of local x_m/y_m positions (WGS84 degrees)\n"
    "  --image-times FILE  CSV image,time_s when the navigation is a time series\n"
    "  --config FILE       build settings (JSON, see config/)\n"
    "  --enhance OPS       enhancement chain, e.g. default or flatfield,dehaze,clahe (see enhance)\n"
    "  --tile-format F     png | jpg | webp        --tile-size 256|512\n"
    "  --base-zoom Z       --min-zoom Z            --threads N\n"
    "  --name TEXT         map name in the metadata\n"
    "  --append            continue painting an existing map (tiles are read back and blended);\n"
    "                      frames whose image is already in it are skipped\n"
    "  --resume            continue an interrupted build (same arguments) from its last checkpoint\n"
    "  --overwrite         replace an existing map\n"
    "  --quiet             no progress bar\n"
    "  --report FILE       write the run's figures as JSON (frames, seconds, tiles, bytes, peak RSS)\n"
    "  --refine-nav        refine the navigation from the photos first (seamap trajectory --mode refine),\n"
    "                      then paint with the refined poses; the mission keeps the navigation's beside them\n"
    "  --detect            search tiles for objects as they are finished (seamap detect's recogniser)\n"
    "  --detect-model FILE its ONNX model (default: data/models/seabed_objects.onnx)\n";

std::string Summary(const BuildStats& s) {
  std::map<std::string, int> reasons;
  for (const auto& r : s.rejections) ++reasons[r.reason.substr(0, r.reason.find(':'))];
  std::ostringstream out;
  out << "frames used " << s.frames_used << ", rejected " << s.rejections.size();
  if (!reasons.empty()) {
    out << " (";
    bool first = true;
    for (const auto& [reason, n] : reasons) {
      out << (first ? "" : ", ") << n << " " << reason;
      first = false;
    }
    out << ")";
  }
  int64_t distinct = 0;
  for (const auto& [z, n] : s.tiles_per_zoom) distinct += n;
  out << "; tiles written " << distinct << " (" << s.tiles_written << " writes, " << s.tile_bytes / 1024 << " KiB); "
      << std::fixed;
  out.precision(2);
  out << s.seconds << " s";
  if (s.seconds > 0) {
    out.precision(1);
    out << " (" << s.frames_seen / s.seconds << " frames/s)";
  }
  return out.str();
}

// in_map: frames skipped by --append because their image is in the map already.
void WriteReport(const std::string& path, const BuildStats& s, const MosaicPlan& plan, const nlohmann::json& refine,
                 size_t in_map) {
  int64_t distinct = 0;
  nlohmann::json per_zoom = nlohmann::json::object();
  for (const auto& [z, n] : s.tiles_per_zoom) {
    distinct += n;
    per_zoom[std::to_string(z)] = n;
  }
  nlohmann::json j = {{"frames_seen", s.frames_seen},
                      {"frames_used", s.frames_used},
                      {"frames_rejected", s.rejections.size()},
                      {"seconds", s.seconds},
                      {"ms_per_frame", s.frames_seen ? 1000 * s.seconds / s.frames_seen : 0},
                      {"frames_per_s", s.seconds > 0 ? s.frames_seen / s.seconds : 0},
                      {"cpu_ms_per_frame", s.frames_seen ? 1000 * s.cpu_seconds / s.frames_seen : 0},
                      {"tiles", distinct},
                      {"tile_writes", s.tiles_written},
                      {"tile_bytes", s.tile_bytes},
                      {"readbacks", s.readbacks},
                      {"frames_in_map", in_map},
                      {"checkpoints", s.checkpoints},
                      {"checkpoint_seconds", s.checkpoint_seconds},
                      {"tiles_per_zoom", per_zoom},
                      {"base_zoom", plan.base_zoom},
                      {"min_zoom", plan.min_zoom},
                      {"peak_rss_bytes", PeakRssBytes()}};
  if (!refine.is_null()) j["refine"] = refine;
  std::ofstream out(path);
  if (!out) throw InputError(path, 0, "--report", "cannot write the report file");
  out << j.dump(2) << "\n";
}

// A word as a POSIX shell reads it back.
std::string ShellWord(const std::string& w) {
  const bool plain = !w.empty() && w.find_first_not_of(
                                       "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                       "0123456789_@%+=:,./-") == std::string::npos;
  if (plain) return w;
  std::string out = "'";
  for (char c : w) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The command that started this build, to be repeated with --resume if it
// is interrupted: its directory, and its arguments less --resume / --overwrite.
std::string CommandLine(int argc, char** argv, int first) {
  std::error_code ec;
  const std::string dir = std::filesystem::current_path(ec).string();
  std::string out = ec ? std::string() : "cd " + ShellWord(dir) + " && ";
  out += "seamap build";
  for (int i = first; i < argc; ++i)
    if (std::string(argv[i]) != "--resume" && std::string(argv[i]) != "--overwrite") out += " " + ShellWord(argv[i]);
  return out;
}

}  // namespace

int RunBuild(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"append", "overwrite", "resume", "quiet", "refine-nav", "detect", "help"});
  if (args.Flag("help")) {
    std::printf("%s%s", kHelp, kNavigationNoiseHelp);
    return 0;
  }
  BuildInputs in = ReadBuildInputs(args);
  const std::string out = args.Require("out");
  const bool append = args.Flag("append"), overwrite = args.Flag("overwrite"), resume = args.Flag("resume");
  const bool quiet = args.Flag("quiet");
  const bool refine = args.Flag("refine-nav") || in.config.navigation.refine;
  const RefineOptions refine_options = ReadRefineOptions(args, in.config.navigation, in.config.threads);
  const std::optional<std::string> report = args.Get("report");
  const auto detect_model = LiveDetectArgs(args);  // checked before the map is opened
  args.RejectUnknown();

  CheckMemoryFits(in);  // before the map is created
  BuildOutput output = OpenOutput(out, in.config, {append, overwrite, resume});
  const std::unique_ptr<TileStore>& store = output.store;
  // Resuming an append (its checkpoint began after frames already in the map) skips the same frames.
  std::vector<std::string> skipped;  // in the map already
  if (append || (output.checkpoint && output.checkpoint->frame_id_offset > 0)) {
    skipped = SkipFramesInMap(*store, output.checkpoint, &in.frames.frames);
    if (!skipped.empty()) {
      std::string names;
      for (size_t i = 0; i < skipped.size() && i < 3; ++i) names += (i ? ", " : "") + skipped[i];
      std::fprintf(stderr, "seamap build: --append: %zu frames are in the map already and are skipped (%s%s)\n",
                   skipped.size(), names.c_str(), skipped.size() > 3 ? ", ..." : "");
    }
    if (in.frames.frames.empty()) {
      std::printf("nothing to add: every frame is in the map already\n");
      return 0;
    }
  }
  if (output.checkpoint) {
    CheckSameSurvey(*store, *output.checkpoint, in.frames.frames);
    std::fprintf(stderr, "seamap build: resuming after frame %d of %zu (the last checkpoint)\n",
                 output.checkpoint->frame_index + 1, in.frames.frames.size());
  }
  nlohmann::json refine_report;
  if (refine) {
    refine_report = RefineFrames(&in.frames.frames, in.camera, refine_options, quiet);
    nlohmann::json summary = refine_report;
    summary.erase("nav_only");  // the frames say which, one by one
    summary["mode"] = "refine";
    store->SetMetadata("seamap_trajectory", summary.dump());
  }
  MosaicPlan plan = PlanMosaic(in.config.map, in.camera, in.frame, in.frames.frames, in.channels);
  std::fprintf(stderr, "seamap build: %zu frames, GSD %.1f mm at %.3f N -> zooms %d..%d, %s tiles of %d px -> %s\n",
               in.frames.frames.size(), plan.gsd_m * 1000, plan.latitude, plan.min_zoom, plan.base_zoom,
               TileExtension(in.config.map.encoding.format).c_str(), in.config.map.tile_size, out.c_str());
  for (const auto& w : in.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

  // The main layer is raw unless only the enhanced map was asked for; with
  // "both", the enhanced map is built alongside as layer "enhanced".
  BuildHooks enhance = MakeHooks(in);
  const bool both = in.config.layers == "both" && enhance.preprocess;
  if (both)
    in.config.buffer.memory_cap_mb = std::max(16, in.config.buffer.memory_cap_mb / 2);  // two builders share the cap
  // Crash-safe: checkpoints as it goes, so that a build killed at any moment resumes (--resume).
  BuildStart start;
  start.checkpoints = true;
  start.resume = resume;
  start.frames_total = static_cast<int>(in.frames.frames.size());
  start.command = CommandLine(argc, argv, first);
  BuildHooks hooks = both ? BuildHooks{} : enhance;
  std::unique_ptr<LiveDetector> detector;  // searches the main layer's finished tiles
  if (detect_model) {
    detector = StartLiveDetector(detect_model, plan, in.config.map.tile_size, in.frame.origin(), store.get(),
                                 in.config.detect, in.config_source);
    hooks.tile_consumers.push_back(detector.get());
  }
  MosaicBuilder builder(in.config, in.camera, in.frame, plan, store.get(), hooks, start);
  std::unique_ptr<TileStore> enhanced_store;
  std::unique_ptr<MosaicBuilder> enhanced;
  if (both) {
    enhanced_store = store->OpenLayer("enhanced");
    BuildStart layer_start = start;
    layer_start.resume = resume && ReadStoredCheckpoint(*enhanced_store);  // killed before the layer began: it begins
    enhanced = std::make_unique<MosaicBuilder>(in.config, in.camera, in.frame, plan, enhanced_store.get(), enhance,
                                               layer_start);
  }
  store->SetMetadata("seamap_layers", both ? "raw,enhanced" : enhance.preprocess ? "enhanced" : "raw");
  for (const auto& r : in.frames.rejected) builder.Reject(r);
  builder.Foresee(in.frames.frames);  // the whole survey is known: tiles are written once
  if (enhanced) enhanced->Foresee(in.frames.frames);
  ProgressBar progress("frames", static_cast<long>(in.frames.frames.size()), !quiet);
  for (const auto& f : in.frames.frames) {
    builder.Push(f);
    if (enhanced) enhanced->Push(f);
    progress.Update(builder.stats().frames_seen - static_cast<long>(in.frames.rejected.size()));
  }
  if (enhanced) enhanced->Finish();
  builder.Finish();  // last: the mission's "complete" state follows both layers
  progress.Update(static_cast<long>(in.frames.frames.size()));
  progress.Finish();
  const BuildStats& s = builder.stats();
  for (const auto& r : s.rejections) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
  std::printf("%s%s\n", Summary(s).c_str(),
              skipped.empty() ? "" : ("; " + std::to_string(skipped.size()) + " already in the map, skipped").c_str());
  if (enhanced) std::printf("enhanced layer: %s\n", Summary(enhanced->stats()).c_str());
  if (detector) FinishLiveDetector(*detector, *store);
  if (report) WriteReport(*report, s, plan, refine_report, skipped.size());
  if (s.frames_used == 0) {
    std::fprintf(stderr, "seamap build: error: no frame could be used\n");
    return 1;
  }
  return 0;
}

}  // namespace seamap::cli
