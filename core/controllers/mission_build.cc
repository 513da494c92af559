#include "core/controllers/mission_build.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "core/enhance/enhance_chain.h"
#include "core/mission/mission_metadata.h"
#include "core/mission/relief_layer.h"
#include "core/mosaic/frame_image.h"
#include "core/tiles/tile_codec.h"
#include "core/util/error.h"

namespace seamap {

void MissionBuildOptions::Check() const {
  if (out.empty()) throw InputError("", 0, "--out", "names no map");
  if (live && resume) throw InputError(out, 0, "--resume", "a live build keeps no checkpoints to resume from");
  if (live && poses.mode == PoseMode::kRefine)
    throw InputError("", 0, "--refine-nav", "needs the whole survey; a live build places frames as they come");
  if (live && config.terrain.estimate)
    throw InputError(config_source, 0, "terrain",
                     "estimating the seabed needs the whole survey; a live build takes a height model's file");
  if (static_cast<bool>(start_detector) != static_cast<bool>(finish_detector))
    throw std::logic_error("MissionBuildOptions: start_detector and finish_detector go together");
  poses.Check();
}

MissionBuild::MissionBuild(MissionBuildOptions options, MissionObserver observer)
    : options_((options.Check(), std::move(options))),
      observer_(std::move(observer)),
      poses_(options_.camera, options_.poses) {}

MissionBuild::~MissionBuild() = default;

TileStore* MissionBuild::store() const {
  return observed_ ? observed_.get() : output_.store.get();
}

const BuildStats& MissionBuild::stats() const {
  if (!builder_) throw std::logic_error("MissionBuild::stats before Start");
  return builder_->stats();
}

const BuildStats* MissionBuild::enhanced_stats() const {
  return enhanced_ ? &enhanced_->stats() : nullptr;
}

bool MissionBuild::Open() {
  BuildConfig& config = options_.config;
  std::vector<FrameSpec>& frames = options_.survey.frames;
  if (options_.live) {  // a live map: publish tiles every few frames (a build batches 25 for speed)
    config.buffer.batch_frames = std::min(config.buffer.batch_frames, 5);
    config.buffer.live_tiles = true;
  }
  // The tile buffer must hold one frame of the survey: refused before the map is created.
  int cap_mb = config.buffer.memory_cap_mb;
  if (config.layers == "both" && config.enhance) cap_mb = std::max(16, cap_mb / 2);  // two builders share it
  CheckPlanFitsMemory(PlanMosaic(config.map, options_.camera, options_.frame, frames, options_.channels),
                      options_.camera, config.map.tile_size, cap_mb,
                      options_.config_source == "build config" ? "" : options_.config_source);
  // A height model's file is read before the map is created: a bad file leaves no map behind.
  if (!config.terrain.file.empty()) {
    surface_ = ReadSeabedSurface(config.terrain.file, options_.frame, options_.camera, frames);
    CheckAgainstNavigation(options_.camera, frames, "--terrain-file", &surface_);
  }
  // The seabed's shape from the photos, on the poses they are painted with.
  const auto estimate_surface = [&] {
    if (observer_.on_note) observer_.on_note("estimating the seabed's shape from the photos");
    surface_ = EstimateSeabedSurface(options_.frame, options_.camera, frames, config.terrain, config.threads,
                                     !options_.poses.quiet, config.frames.max_image_pixels, &poses_.seabed_points());
  };
  // On the navigation's poses it comes before the map is created, so photos
  // that give no seabed leave no map behind; refined poses are placed once
  // the map is open (their report goes into it), and the estimate follows them.
  const bool estimate_first = config.terrain.estimate && poses_.mode() == PoseMode::kNavigation;
  if (estimate_first) estimate_surface();
  output_ = OpenOutput(options_.out, config, {options_.append, options_.overwrite, options_.resume});
  TileStore& store = *output_.store;
  if (!options_.live) {
    // Resuming an append (its checkpoint began after frames already in the map) skips the same frames.
    if (options_.append || (output_.checkpoint && output_.checkpoint->frame_id_offset > 0)) {
      SkipFramesInMap();
      if (frames.empty()) return false;
    }
    if (output_.checkpoint) {
      CheckSameSurvey(store, *output_.checkpoint, frames);
      if (observer_.on_note)
        observer_.on_note("resuming after frame " + std::to_string(output_.checkpoint->frame_index + 1) + " of " +
                          std::to_string(frames.size()) + " (the last checkpoint)");
    }
    if (poses_.mode() != PoseMode::kNavigation) {
      pose_report_ = poses_.PlaceSurvey(&frames);
      nlohmann::json summary = pose_report_;
      summary.erase("nav_only");  // the frames say which, one by one
      summary["mode"] = poses_.name();
      MissionMetadata mission;
      mission.trajectory = summary;
      WriteMissionMetadata(&store, mission);
    }
  }
  if (config.terrain.estimate && !estimate_first) estimate_surface();
  if (surface_.grid) {
    CheckAgainstNavigation(options_.camera, frames, config.terrain.file.empty() ? "--terrain" : "--terrain-file",
                           &surface_);
    if (observer_.on_note) observer_.on_note(surface_.Summary());
  }
  plan_ = PlanMosaic(config.map, options_.camera, options_.frame, frames, options_.channels);
  // The height model is kept in the mission with its relief layer (the map's
  // zooms are known from here on; a live console sees the layer from the start).
  if (surface_.grid) StoreMissionTerrain(&store, {*surface_.grid, options_.frame.origin()}, !options_.poses.quiet);

  // The main layer is raw unless only the enhanced map was asked for; with
  // "both", the enhanced map is built alongside as layer "enhanced".
  if (config.enhance && config.layers != "raw") {
    auto chain = std::make_shared<EnhanceChain>(EnhanceChain::FromJson(*config.enhance, options_.config_source));
    // Stateful ops (the flat field) learn from the survey's first frames.
    std::vector<cv::Mat> samples;
    for (const auto& f : frames) {
      if (static_cast<int>(samples.size()) >= chain->SeedFrames()) break;
      // Read as the build reads frames: FIFOs and oversized images are left out.
      std::string problem;
      auto image = FrameImage::Read(f.image_path, options_.channels, config.frames.sixteen_bit_white, &problem,
                                    config.frames.max_image_pixels);
      if (image && image->width() == options_.camera.width && image->height() == options_.camera.height) {
        try {
          samples.push_back(image->Full().clone());
        } catch (const InputError&) {  // broken JPEG data: the build reports it
        }
      }
    }
    if (!samples.empty()) chain->Seed(samples);
    enhance_.preprocess = [chain](const cv::Mat& frame) { return chain->Apply(frame); };
  }
  both_ = config.layers == "both" && enhance_.preprocess;
  layers_ = both_ ? std::vector<std::string>{"raw", "enhanced"}
                  : std::vector<std::string>{enhance_.preprocess ? "enhanced" : "raw"};
  if (options_.live) {
    WriteLiveMetadata();
    observed_ = std::make_unique<ObservedStore>(
        &store, [this](const std::string& layer, const std::vector<CommittedTile>& done) {
          if (observer_.on_tiles_committed) observer_.on_tiles_committed(layer, done);
        });
  }
  return true;
}

void MissionBuild::SkipFramesInMap() {
  skipped_ = seamap::SkipFramesInMap(*output_.store, output_.checkpoint, &options_.survey.frames);
  if (skipped_.empty() || !observer_.on_note) return;
  std::string names;
  for (size_t i = 0; i < skipped_.size() && i < 3; ++i) names += (i ? ", " : "") + skipped_[i];
  observer_.on_note("--append: " + std::to_string(skipped_.size()) +
                    " frames are in the map already and are skipped (" + names + (skipped_.size() > 3 ? ", ..." : "") +
                    ")");
}

// What a client needs before the first batch lands.
void MissionBuild::WriteLiveMetadata() {
  TileStore& store = *output_.store;
  store.SetMetadata("name", options_.config.map.name);
  store.SetMetadata("format", TileExtension(options_.config.map.encoding.format));
  store.SetMetadata("minzoom", std::to_string(plan_->min_zoom));
  store.SetMetadata("maxzoom", std::to_string(plan_->base_zoom));
  MissionMetadata mission;
  mission.layers = layers_;
  mission.state = "building";
  if (poses_.mode() != PoseMode::kNavigation) mission.trajectory = nlohmann::json{{"mode", poses_.name()}};
  mission.origin = options_.frame.origin();
  WriteMissionMetadata(&store, mission);
  store.Flush();
}

void MissionBuild::Start() {
  if (!plan_) throw std::logic_error("MissionBuild::Start before Open");
  BuildConfig& config = options_.config;
  if (both_) config.buffer.memory_cap_mb = std::max(16, config.buffer.memory_cap_mb / 2);  // two builders share the cap
  BuildStart start;
  if (!options_.live) {  // crash-safe: checkpoints as it goes, so that a build killed at any moment resumes
    start.checkpoints = true;
    start.resume = options_.resume;
    start.frames_total = static_cast<int>(options_.survey.frames.size());
    start.command = options_.command;
  }
  enhance_.surface = surface_.painted;  // both layers paint onto the same seabed
  BuildHooks hooks = both_ ? BuildHooks{} : enhance_;
  hooks.on_frame = observer_.on_frame_placed;
  hooks.surface = surface_.painted;
  TileStore* raw_store = output_.store.get();
  if (options_.start_detector) {
    detector_ = options_.start_detector(*plan_, raw_store);
    hooks.tile_consumers.push_back(detector_.get());
    // Live: what is found so far every second (the console shows objects as they are found).
    if (observer_.on_objects_found)
      detector_->OnFound(
          observer_.on_objects_found, [raw_store] { return raw_store->Records().Frames(); }, std::chrono::seconds(1));
  }
  builder_ = std::make_unique<MosaicBuilder>(config, options_.camera, options_.frame, *plan_, store(), hooks, start);
  if (both_) {
    enhanced_store_ = store()->OpenLayer("enhanced");
    BuildStart layer_start = start;
    layer_start.resume =
        start.resume && ReadStoredCheckpoint(*enhanced_store_);  // killed before the layer began: it begins
    enhanced_ = std::make_unique<MosaicBuilder>(config, options_.camera, options_.frame, *plan_, enhanced_store_.get(),
                                                enhance_, layer_start);
  }
  if (!options_.live) {
    MissionMetadata mission;
    mission.layers = both_ ? std::vector<std::string>{"raw", "enhanced"} : std::vector<std::string>{layers_[0]};
    WriteMissionMetadata(raw_store, mission);
  }
}

void MissionBuild::Run() {
  if (!builder_) throw std::logic_error("MissionBuild::Run before Start");
  const FrameList& survey = options_.survey;
  for (const auto& r : survey.rejected) builder_->Reject(r);
  builder_->Foresee(survey.frames);  // the whole survey is known: tiles are written once
  if (enhanced_) enhanced_->Foresee(survey.frames);
  for (const auto& f : survey.frames) {
    builder_->Push(f);
    if (enhanced_) enhanced_->Push(f);
    if (observer_.on_progress) observer_.on_progress(builder_->stats());
  }
  Finish();
}

void MissionBuild::Run(FrameFeed& feed) {
  if (!builder_) throw std::logic_error("MissionBuild::Run before Start");
  while (auto item = feed.Next()) {
    if (item->rejection) {
      builder_->Reject(*item->rejection);
      if (enhanced_) enhanced_->Reject(*item->rejection);
    } else {
      FrameSpec frame = *item->frame;
      const cv::Mat decoded = poses_.Place(&frame);  // the filter's read, painted from too
      builder_->Push(frame, decoded);
      if (enhanced_) enhanced_->Push(frame, decoded);
    }
    if (observer_.on_progress) observer_.on_progress(builder_->stats());
  }
  Finish();
}

void MissionBuild::Finish() {
  if (enhanced_) enhanced_->Finish();
  builder_->Finish();  // last: the mission's "complete" state follows both layers
  if (observer_.on_layers_finished) observer_.on_layers_finished();
  if (detector_) options_.finish_detector(*detector_, *output_.store, observer_.on_objects_found);
}

void MissionBuild::Conclude(bool complete) {
  if (!complete) {
    MissionMetadata mission;
    mission.state = "stopped";
    WriteMissionMetadata(output_.store.get(), mission);
  }
  output_.store->Flush();
}

}  // namespace seamap
