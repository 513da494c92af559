#include "core/controllers/mission_build.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "core/camera/frame_projector.h"
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
    throw InputError("", 0, "--refine-nav",
                     "a live build refines the frames as they come (refine_live), not the whole survey first");
  if (refine_live && !live) throw std::logic_error("MissionBuildOptions: refine_live is for live builds");
  if (refine_live && append)
    throw InputError(out, 0, "--append", "replay --refine-nav paints the whole mission again; give a new map");
  if (refine_live) poses.refine.Check();
  if (live && config.terrain.estimate && append)
    throw InputError(out, 0, "--append", "replay --terrain paints the whole mission again; give a new map");
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
  offline_config_ = config;
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
  // Live, the seabed is estimated at the end of the dive (FinishLiveMission): painted flat until then.
  const bool estimate_first = config.terrain.estimate && poses_.mode() == PoseMode::kNavigation && !options_.live;
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
  if (config.terrain.estimate && !estimate_first && !options_.live) estimate_surface();
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
  if (options_.refine_live) mission.trajectory = nlohmann::json{{"mode", "refine"}, {"live", true}};
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
  if (options_.refine_live || TerrainAtEnd()) {  // the whole map is painted again at the end
    repaint_.config = offline_config_;
    repaint_.camera = options_.camera;
    repaint_.frame = options_.frame;
    repaint_.plan = *plan_;
    repaint_.hooks.surface = surface_.painted;
    repaint_.hooks.preprocess = both_ ? nullptr : enhance_.preprocess;
  }
  if (options_.refine_live) {
    hooks.on_frame = [this](const FrameRecord& record, const TrackPoint& point) {
      {  // which frames the worker may correct: those recorded as painted
        std::lock_guard<std::mutex> lock(recorded_mutex_);
        if (record.id >= 0) {
          if (static_cast<size_t>(record.id) >= recorded_.size()) recorded_.resize(record.id + 1, 0);
          recorded_[record.id] = record.status == "used";
        }
      }
      if (observer_.on_frame_placed) observer_.on_frame_placed(record, point);
    };
    LiveRefinerOptions live;
    live.refine = options_.poses.refine;
    live.refine.max_image_pixels = config.frames.max_image_pixels;
    live.base_pixel_m = MetersPerPixel(plan_->latitude, plan_->base_zoom, config.map.tile_size);
    live.max_feature_bytes = options_.refine_live_feature_bytes;
    refiner_ = std::make_unique<LiveRefiner>(options_.camera, live,
                                             [this](const LiveCorrection& correction) { Repaint(correction); });
  }
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
      if (options_.refine_live) {  // refined from the navigation, as build --refine-nav refines
        FrameSpec nav = frame;
        if (nav.nav_pose) nav.pose = *nav.nav_pose;
        nav.nav_pose.reset();
        live_frames_.push_back(nav);
        refiner_->Add(nav, frame.pose);
      } else if (TerrainAtEnd()) {  // painted again onto the seabed estimated at the end, at these poses
        live_frames_.push_back(frame);
      }
    }
    if (observer_.on_progress) observer_.on_progress(builder_->stats());
  }
  // Stopped (Ctrl-C): the mission is kept as painted, without the final refinement's minutes.
  if (feed.stopped()) live_frames_.clear();
  Finish();
}

void MissionBuild::Finish() {
  if (refiner_) refiner_->Stop();  // its last repaint done; the final solve follows
  if (enhanced_) enhanced_->Finish();
  builder_->Finish();  // last: the mission's "complete" state follows both layers
  if (options_.refine_live || TerrainAtEnd()) FinishLiveMission();
  if (observer_.on_layers_finished) observer_.on_layers_finished();
  if (detector_) options_.finish_detector(*detector_, *output_.store, observer_.on_objects_found);
}

std::optional<LiveRefinerLag> MissionBuild::refine_lag() const {
  if (!refiner_) return std::nullopt;
  return refiner_->Lag();
}

void MissionBuild::Repaint(const LiveCorrection& correction) {
  const std::vector<FrameSpec>& placed = correction.placed;
  const std::vector<int>& moved = correction.moved;
  const std::vector<VehiclePose>& before = correction.before;
  const int zoom = plan_->base_zoom, ts = repaint_.config.map.tile_size;
  TileSet tiles;
  for (size_t k = 0; k < moved.size(); ++k)
    for (const VehiclePose& pose : {before[k], placed[moved[k]].pose})
      for (const TileId& t : FrameTiles(options_.camera, options_.frame, pose, zoom, ts)) tiles.insert(t);
  const RepaintResult painted = RepaintTiles(store(), repaint_, placed, tiles);
  SearchAgain(painted.written);  // the objects on them follow the correction
  std::string enhanced_tiles;
  if (enhanced_store_) {  // layers: both: the enhanced layer's tiles too, from the same frames
    RepaintSetup enhanced = repaint_;
    enhanced.hooks.preprocess = enhance_.preprocess;
    enhanced_tiles =
        ", enhanced " + std::to_string(RepaintTiles(enhanced_store_.get(), enhanced, placed, tiles).base_tiles);
  }
  // The moved frames' records at their corrected poses (the console's track).
  int corrected = 0;
  for (int i : moved) {
    const FrameSpec& f = placed[i];
    {
      std::lock_guard<std::mutex> lock(recorded_mutex_);
      if (f.index >= static_cast<int>(recorded_.size()) || !recorded_[f.index]) continue;
    }
    const auto corners = Footprint(options_.camera, f.pose);
    if (!corners) continue;
    FrameRecord record;
    record.id = f.index;
    record.image = f.image;
    record.image_path = f.image_path;
    record.time_s = f.time_s;
    record.position = options_.frame.ToLatLon({f.pose.east_m, f.pose.north_m});
    record.altitude_m = f.pose.altitude_m;
    record.depth_m = f.pose.depth_m;
    record.heading_deg = f.pose.heading_deg;
    record.pitch_deg = f.pose.pitch_deg;
    record.roll_deg = f.pose.roll_deg;
    for (int k = 0; k < 4; ++k) record.footprint[k] = options_.frame.ToLatLon((*corners)[k]);
    record.status = "used";
    if (f.nav_pose) {
      const VehiclePose& nav = *f.nav_pose;
      record.nav = NavigatedPose{options_.frame.ToLatLon({nav.east_m, nav.north_m}),
                                 nav.altitude_m,
                                 nav.depth_m,
                                 nav.heading_deg,
                                 nav.pitch_deg,
                                 nav.roll_deg};
    }
    TrackPoint point;
    point.seq = i;  // a new mission's points follow the frames painted, one each
    point.time_s = f.time_s;
    point.position = record.position;
    point.altitude_m = record.altitude_m;
    point.depth_m = record.depth_m;
    point.heading_deg = record.heading_deg;
    if (record.nav) point.nav = NavigatedPosition{record.nav->position, record.nav->heading_deg};
    store()->Records().PutFrame(record);
    store()->Records().PutTrackPoint(point);
    if (observer_.on_frame_placed) observer_.on_frame_placed(record, point);
    ++corrected;
  }
  store()->Flush();
  // The seams this solve closed: its pairs' disagreement with the navigation and with the solution.
  const IncrementalSolution& s = correction.solution;
  std::fprintf(stderr,
               "\nrefine live: solve %d over %d frames, %d cross-pass and %d along-track pairs; pair residual RMS "
               "%.1f mm -> %.1f mm; %zu frames moved more than a pixel painted again (%zu tiles%s)\n",
               correction.solve, s.frames, s.registered_cross, s.registered_along, s.residual_before_mm,
               s.residual_after_mm, moved.size(), painted.base_tiles, enhanced_tiles.c_str());
  if (observer_.on_trajectory_corrected) observer_.on_trajectory_corrected(corrected, false);
}

void MissionBuild::SearchAgain(const TileSet& tiles) {
  if (!detector_) return;
  for (const TileId& id : tiles) detector_->OnTileWritten(id, cv::Mat(), 0, true);
}

bool MissionBuild::TerrainAtEnd() const {
  return options_.live && options_.config.terrain.estimate;
}

void MissionBuild::FinishLiveMission() {
  {
    MissionMetadata mission;  // not complete until it is refined and painted again
    mission.state = "building";
    WriteMissionMetadata(output_.store.get(), mission);
    output_.store->Flush();
  }
  if (live_frames_.empty()) return;  // nothing painted, or stopped: left as it is
  std::optional<PoseSource> final_poses;
  int moved = 0;
  if (options_.refine_live) {  // the whole dive refined as build --refine-nav refines it
    PoseSourceOptions refine = options_.poses;
    refine.mode = PoseMode::kRefine;
    final_poses.emplace(options_.camera, refine);
    pose_report_ = final_poses->PlaceSurvey(&live_frames_);
    nlohmann::json summary = pose_report_;
    summary.erase("nav_only");  // the frames say which, one by one
    summary["mode"] = "refine";
    summary["live"] = true;
    MissionMetadata mission;
    mission.trajectory = summary;
    WriteMissionMetadata(output_.store.get(), mission);
    for (const FrameSpec& f : live_frames_) moved += f.nav_pose.has_value();
  }
  RepaintSetup setup = repaint_;
  if (TerrainAtEnd()) {  // --terrain: the seabed from the photos at their final poses, as build estimates it
    const BuildConfig& config = options_.config;
    if (observer_.on_note) observer_.on_note("estimating the seabed's shape from the photos");
    try {
      surface_ = EstimateSeabedSurface(options_.frame, options_.camera, live_frames_, config.terrain, config.threads,
                                       !options_.poses.quiet, config.frames.max_image_pixels,
                                       final_poses ? &final_poses->seabed_points() : nullptr);
      CheckAgainstNavigation(options_.camera, live_frames_, "--terrain", &surface_);
      if (observer_.on_note) observer_.on_note(surface_.Summary());
    } catch (const InputError& e) {  // the dive is not lost for it: its map stays on the plane
      std::fprintf(stderr, "\nwarning: %s; the map stays painted on the plane\n", e.what());
      surface_ = SeabedSurface{};
    }
    if (surface_.grid)
      StoreMissionTerrain(output_.store.get(), {*surface_.grid, options_.frame.origin()}, !options_.poses.quiet);
    setup.hooks.surface = surface_.painted;
  }
  setup.hooks.on_frame = observer_.on_frame_placed;  // the final records, to the server too
  SearchAgain(RepaintWholeMap(store(), setup, live_frames_).written);
  if (enhanced_store_) {
    setup.hooks.preprocess = enhance_.preprocess;
    setup.hooks.on_frame = nullptr;
    RepaintWholeMap(enhanced_store_.get(), setup, live_frames_);
  }
  if (options_.refine_live && observer_.on_trajectory_corrected) observer_.on_trajectory_corrected(moved, true);
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
