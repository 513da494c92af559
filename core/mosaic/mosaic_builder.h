#pragma once
// Builds a map from frames: the orchestra of the frame pipeline (load, check,
// enhance, warp), the tile buffer (blend into base tiles, finish them when
// their time has come), the tile writer and overview pyramid (encode, store,
// hand to the tile consumers) and the mission recorder (frames, track, state).
//
//   FrameSpec (pose: where the frame is placed) -> FramePipeline -> PlacedFrame
//     -> MissionRecorder (frames, track) and TileBuffer (blend)
//     -> finished tiles -> TileWriter (store, TileConsumers) and OverviewPyramid
//
// Seams: the pose each frame is placed with is FrameSpec::pose, set by
// whoever makes the FrameSpecs (the navigation, or a corrected trajectory);
// finished tiles reach TileConsumers (BuildHooks::tile_consumers).
//
// Crash safety (BuildStart): an offline build writes checkpoints
// (build_checkpointer.h) when its store keeps them, and a builder can start
// from the last one instead of from scratch.
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/geo/local_frame.h"
#include "core/geo/web_mercator.h"
#include "core/mosaic/build_checkpointer.h"
#include "core/mosaic/build_config.h"
#include "core/mosaic/frame_pipeline.h"
#include "core/mosaic/frame_warper.h"
#include "core/mosaic/mission_recorder.h"
#include "core/mosaic/mosaic_plan.h"
#include "core/mosaic/overview_pyramid.h"
#include "core/mosaic/tile_buffer.h"
#include "core/mosaic/tile_consumer.h"
#include "core/mosaic/tile_forecast.h"
#include "core/mosaic/tile_writer.h"
#include "core/nav/frame_list.h"
#include "core/tiles/tile_store.h"
#include "core/util/thread_pool.h"

namespace seamap {

struct BuildStats {
  int frames_seen = 0;
  int frames_used = 0;
  std::vector<Rejection> rejections;  // frames skipped, with reasons
  int64_t tiles_written = 0;          // store writes, rewrites included
  int64_t tile_bytes = 0;
  std::map<int, int64_t> tiles_per_zoom;  // distinct tiles
  int64_t readbacks = 0;                  // tiles read back to continue painting
  double seconds = 0;
  double cpu_seconds = 0;         // process CPU time (all threads) over the same span
  int checkpoints = 0;            // written by this run (BuildStart::checkpoints)
  double checkpoint_seconds = 0;  // spent writing them
};

struct BuildHooks {
  // A frame went through (used or rejected) with the track point stored for it; builder's thread.
  std::function<void(const FrameRecord&, const TrackPoint&)> on_frame;
  // Applied to every 8-bit frame before warping (the enhancement chain); thread-safe.
  std::function<cv::Mat(const cv::Mat&)> preprocess;
  // Each gets every tile written (TileConsumer); they must outlive the builder.
  std::vector<TileConsumer*> tile_consumers;
  // The seabed's height model, when frames are projected onto it (a true
  // orthophoto, `build --terrain`); null: the plane at each frame's altitude.
  std::shared_ptr<const HeightGrid> surface;
};

// How a builder meets its store.
struct BuildStart {
  // Save checkpoints every `checkpoint_seconds` (BufferSettings) when the
  // store keeps them. A builder destroyed unfinished then returns a map that
  // was complete before it (--append) to its previous tiles and state, unless
  // it had checkpointed frames (then the map is interrupted, and resumable).
  bool checkpoints = false;
  // Continue from the store's checkpoint (it must have one, written by a
  // build of the same survey and settings): frames up to it are not painted
  // again. InputError naming the setting when the settings differ.
  bool resume = false;
  int frames_total = 0;  // frames in the survey (recorded in checkpoints)
  // The command line that started the build (its --resume hint; "": none).
  std::string command;
};

class MosaicBuilder {
 public:
  MosaicBuilder(const BuildConfig& config, const CameraModel& camera, const LocalFrame& frame, const MosaicPlan& plan,
                TileStore* store, BuildHooks hooks = {}, const BuildStart& start = {});
  ~MosaicBuilder();

  // Offline builds: the whole survey, before the first Push. A tile is then
  // kept in the buffer while a frame among the next `lookahead_frames` will
  // be over it, so a survey line returning to it does not read it back.
  void Foresee(const std::vector<FrameSpec>& frames);
  // Queues a frame; blocks while the pipeline is full. Frames must come in
  // acquisition order. A resumed builder passes over those done before.
  // `decoded`: the frame's photo already decoded (cv::imread, unchanged) by
  // whoever placed it; painted from instead of the file (FramePipeline::Push).
  void Push(const FrameSpec& frame, const cv::Mat& decoded = cv::Mat());
  // Rejects a frame before it enters the pipeline (e.g. navigation problems).
  void Reject(const Rejection& rejection);
  // Blends everything queued, writes all tiles, overviews and metadata, commits.
  void Finish();

  const BuildStats& stats() const { return stats_; }
  const MosaicPlan& plan() const { return plan_; }
  // A resumed builder: the acquisition index of the last frame its checkpoint had (else -1).
  int resumed_after() const { return resume_index_; }

  // What shapes the tiles: a build resumed with other values would not
  // finish the map it began (keys as in the config file).
  static nlohmann::json Settings(const BuildConfig& config, const MosaicPlan& plan, bool enhanced);

 private:
  void Consume(PlacedFrame placed);  // a frame out of the pipeline, in acquisition order
  void FlushBatch();
  void Finished(const TileId& id, const cv::Mat& tile);  // a base tile is finished
  void UpdateWriteStats();
  // keep_start: the first checkpoint of an append to a complete map (see CheckpointUpdate).
  void WriteCheckpoint(bool keep_start = false);
  void Resume();
  void Abandon();  // unfinished: see BuildStart::checkpoints

  BuildConfig config_;
  MosaicPlan plan_;
  TileStore* store_;
  BuildHooks hooks_;
  FrameWarper warper_;
  std::unique_ptr<ThreadPool> pool_;
  std::unique_ptr<TileWriter> writer_;
  std::unique_ptr<OverviewPyramid> pyramid_;
  TileForecast forecast_;
  TileBuffer buffer_;
  MissionRecorder recorder_;
  BuildStart mode_;
  std::unique_ptr<BuildCheckpointer> checkpointer_;  // null: no checkpoints
  std::unique_ptr<FramePipeline> pipeline_;          // last: its jobs use the members above
  int consumed_ = 0;                                 // frames out of the pipeline so far
  int last_index_ = -1;                              // acquisition index of the last of them
  BuildStats stats_;
  std::chrono::steady_clock::time_point start_, last_flush_;
  double start_cpu_ = 0;
  int last_flush_frame_ = 0;
  bool finished_ = false;
  int handover_index_ = -1;     // the last consumed frame that reached the warp
  int resume_index_ = -1;       // frames up to this one were done before the checkpoint
  int prime_from_ = 0;          // frames from this one on go through the pipeline
  int checkpoint_index_ = -1;   // frame_index of the last checkpoint written or resumed from
  std::string previous_state_;  // the map's state before this build began
  std::chrono::steady_clock::time_point last_checkpoint_;
};

}  // namespace seamap
