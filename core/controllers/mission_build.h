#pragma once
// A mission built from a survey's frames: what `seamap build` and `seamap
// replay` both run (options -> Check() -> Open() -> Start() -> Run()).
//
// It owns the map (opened as the options ask: new, --append, --overwrite,
// --resume), its layers (raw, enhanced, or both side by side) with the
// enhancement chain seeded from the first frames, the pose source that
// places each frame, the recogniser searching finished tiles (LiveDetector),
// and the checkpoints of an offline build. Frames come from the whole survey
// known in advance (Run(FrameList): tiles are written once, Foresee) or one
// at a time from a FrameFeed (live: tiles are published every few frames).
//
// What a live server needs reaches it through MissionObserver: the
// controller knows nothing of HTTP.
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/camera/camera_model.h"
#include "core/controllers/live_refiner.h"
#include "core/controllers/map_output.h"
#include "core/controllers/map_repaint.h"
#include "core/controllers/pose_source.h"
#include "core/controllers/seabed_surface.h"
#include "core/detect/live_detector.h"
#include "core/geo/local_frame.h"
#include "core/mosaic/build_config.h"
#include "core/mosaic/mosaic_builder.h"
#include "core/mosaic/mosaic_plan.h"
#include "core/nav/frame_feed.h"
#include "core/nav/frame_list.h"
#include "core/tiles/observed_store.h"
#include "core/tiles/tile_store.h"

namespace seamap {

struct MissionBuildOptions {
  BuildConfig config;
  std::string config_source = "build config";  // the file it came from, for errors
  CameraModel camera;
  LocalFrame frame{LatLon{0, 0}};
  // The survey as known at the start: the map is planned from it, and
  // Run(FrameList) paints it (a live build may get more frames from its feed).
  FrameList survey;
  int channels = 1;
  std::string out;  // NAME.mbtiles or a folder
  bool append = false, overwrite = false, resume = false;
  // Live (replay): tiles published every few frames, the metadata a client
  // needs written before the first frame, no checkpoints, no --resume.
  bool live = false;
  // Offline: the command line that started the build (the checkpoints' --resume hint).
  std::string command;
  PoseSourceOptions poses;
  // Live only (replay --refine-nav): the frames are painted as `poses` places
  // them, refined from the photos as they come on a worker (LiveRefiner), the
  // tiles of frames that moved painted again; at the end the whole survey is
  // refined as build --refine-nav refines it (poses.refine) and painted again.
  bool refine_live = false;
  // refine_live: the worker's resident features at most this (0: no bound; LiveRefinerOptions).
  size_t refine_live_feature_bytes = LiveRefinerOptions{}.max_feature_bytes;
  // The recogniser (--detect): made once the map is planned, drained after
  // the layers are finished (its summary is the caller's to print). Both or neither.
  std::function<std::unique_ptr<LiveDetector>(const MosaicPlan&, const TileStore* store)> start_detector;
  std::function<void(LiveDetector&, TileStore&, const LiveDetector::Found& publish)> finish_detector;
  // InputError naming the option that does not fit.
  void Check() const;
};

// Hooks for whoever watches the mission grow (a live server); all optional.
struct MissionObserver {
  // Offline: what is being done before the first frame ("resuming after ..."), one line each.
  std::function<void(const std::string&)> on_note;
  // A frame went through (used or rejected), with the track point stored for it.
  std::function<void(const FrameRecord&, const TrackPoint&)> on_frame_placed;
  // Live: tiles committed to the map, readable now; layer "" is the main one.
  ObservedStore::Listener on_tiles_committed;
  // After each frame the source handed out.
  std::function<void(const BuildStats&)> on_progress;
  // The recogniser's objects: every second while it searches, and the final
  // ones, which then go there instead of straight into the store.
  LiveDetector::Found on_objects_found;
  // The layers are finished; the recogniser has not drained yet.
  std::function<void()> on_layers_finished;
  // refine_live: the placed trajectory was corrected (frames_moved frames
  // painted again; their records went through on_frame_placed); `final` for
  // the end of the dive's solve.
  std::function<void(int frames_moved, bool final)> on_trajectory_corrected;
};

class MissionBuild {
 public:
  MissionBuild(MissionBuildOptions options, MissionObserver observer = {});
  ~MissionBuild();

  // Opens the map (refusing what does not fit it, InputError naming the
  // option), checks the memory, leaves out frames already in it (append,
  // resume), places the survey when its poses are corrected all at once
  // (refine), plans the map, seeds the enhancement chain. Live, it writes
  // what a client needs to know before the first frame. Returns false when
  // every frame is in the map already (nothing to build).
  bool Open();
  // Makes the recogniser and the layers' builders (a resumed build continues
  // from its checkpoint). After Open, before Run.
  void Start();
  // Paints the whole survey (options' FrameList), finishes the layers and
  // drains the recogniser.
  void Run();
  // Paints the frames a feed hands out until it ends, placing each with the
  // pose source; then the same as Run().
  void Run(FrameFeed& feed);
  // Live, after Run (or its failure): a mission not complete is marked
  // stopped; everything is flushed.
  void Conclude(bool complete);

  const MosaicPlan& plan() const { return *plan_; }
  // The map's store (the recogniser reads it); live: the one that reports
  // commits, for servers to read through.
  TileStore* store() const;
  const std::vector<std::string>& layers() const { return layers_; }  // "raw", "enhanced"
  const std::vector<std::string>& skipped() const { return skipped_; }
  const std::optional<BuildProgress>& resumed_from() const { return output_.checkpoint; }
  const nlohmann::json& pose_report() const { return pose_report_; }  // PlaceSurvey's; null without one
  // The height model painted onto (config.terrain), known after Open; its grid is null when flat.
  const SeabedSurface& surface() const { return surface_; }
  const BuildStats& stats() const;           // the main layer's
  const BuildStats* enhanced_stats() const;  // null without the second layer
  const MissionBuildOptions& options() const { return options_; }
  // refine_live: how far the worker is behind (nullopt otherwise).
  std::optional<LiveRefinerLag> refine_lag() const;

 private:
  void Finish();
  void SkipFramesInMap();
  void WriteLiveMetadata();
  // Live, at the end (refine_live, --terrain): the whole survey refined, its
  // seabed estimated, the map painted again from scratch.
  void FinishLiveMission();
  bool TerrainAtEnd() const;  // live with config.terrain.estimate
  // refine_live, on the worker: tiles of the frames that moved painted again, their records corrected.
  void Repaint(const LiveCorrection& correction);
  // refine_live: the recogniser searches the main layer's tiles painted again
  // (their windows' objects replaced), so the objects follow the corrected map.
  void SearchAgain(const TileSet& tiles);

  MissionBuildOptions options_;
  MissionObserver observer_;
  PoseSource poses_;
  MapOutput output_;
  std::unique_ptr<ObservedStore> observed_;  // live
  std::optional<MosaicPlan> plan_;
  BuildHooks enhance_;  // the enhancement chain's hooks
  bool both_ = false;   // raw and enhanced side by side
  std::vector<std::string> layers_;
  std::vector<std::string> skipped_;
  nlohmann::json pose_report_;
  SeabedSurface surface_;
  std::unique_ptr<LiveDetector> detector_;  // searches the main layer's finished tiles
  std::unique_ptr<MosaicBuilder> builder_;
  std::unique_ptr<TileStore> enhanced_store_;
  std::unique_ptr<MosaicBuilder> enhanced_;
  BuildConfig offline_config_;          // the config before Open made it live (a repaint's)
  std::vector<FrameSpec> live_frames_;  // refine_live: the frames painted so far, navigation poses
  RepaintSetup repaint_;                // refine_live
  std::mutex recorded_mutex_;
  std::vector<int> recorded_;             // refine_live: per frame index, 1 once recorded as used, 0 otherwise
  std::unique_ptr<LiveRefiner> refiner_;  // refine_live
};

}  // namespace seamap
