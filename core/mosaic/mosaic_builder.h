#pragma once
// The frame pipeline: frames are loaded, checked and warped in parallel on a
// thread pool (a frame's warp waits until the next usable frame is loaded: the
// two hand over to each other at a feathered seam, see FrameWarper), then
// blended in acquisition order into base-zoom tiles kept in
// a RAM buffer. A tile is finished when `linger_frames` frames in a row have
// missed it (the seed paper's rule for linger 1) or when the buffer reaches
// its memory cap; finished tiles are encoded and written in the background and
// feed the overview pyramid. A tile that is touched again after it was
// written is read back and blended, never overwritten. In a foreseen survey,
// JPEG frames' side-edge tails (FrameWarper::Warp) wait in PendingTails and
// are decoded only for the pixels no other frame has painted by the time
// their tile is finished.
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/geo/local_frame.h"
#include "core/geo/web_mercator.h"
#include "core/mosaic/build_config.h"
#include "core/mosaic/frame_image.h"
#include "core/mosaic/frame_warper.h"
#include "core/mosaic/overview_pyramid.h"
#include "core/mosaic/pending_tails.h"
#include "core/mosaic/tail_cover.h"
#include "core/mosaic/tile_accumulator.h"
#include "core/mosaic/tile_writer.h"
#include "core/nav/frame_list.h"
#include "core/tiles/tile_store.h"
#include "core/util/thread_pool.h"

namespace seamap {

// Decisions made before the first frame: zooms, colour, bounds estimate.
struct MosaicPlan {
  int base_zoom = 0;
  int min_zoom = 0;
  int channels = 1;     // 1 gray, 3 colour
  double gsd_m = 0;     // ground sample distance at the median altitude
  double latitude = 0;  // survey latitude used for the zoom choice
};

MosaicPlan PlanMosaic(const BuildConfig& config, const CameraModel& camera, const LocalFrame& frame,
                      const std::vector<FrameSpec>& frames, int channels);

struct BuildStats {
  int frames_seen = 0;
  int frames_used = 0;
  std::vector<Rejection> rejections;  // frames skipped, with reasons
  int64_t tiles_written = 0;          // store writes, rewrites included
  int64_t tile_bytes = 0;
  std::map<int, int64_t> tiles_per_zoom;  // distinct tiles
  int64_t readbacks = 0;                  // tiles read back to continue painting
  int tail_frames = 0;                    // frames whose side-edge tail waited (BuildConfig::defer_edge_tails)
  int tail_decodes = 0;                   // times a waiting tail had pixels left to paint (rows decoded)
  int tail_failures = 0;                  // of those, JPEG data broken beyond the rows decoded first: tail not painted
  double seconds = 0;
  double cpu_seconds = 0;  // process CPU time (all threads) over the same span
  std::optional<LatLonBounds> bounds;
};

struct BuildHooks {
  std::function<void(const TileId&, uint64_t version)> on_tile_written;  // worker thread
  // A frame went through (used or rejected) with the track point stored for it; builder's thread.
  std::function<void(const FrameRecord&, const TrackPoint&)> on_frame;
  // Applied to every 8-bit frame before warping (the enhancement chain); thread-safe.
  std::function<cv::Mat(const cv::Mat&)> preprocess;
};

class MosaicBuilder {
 public:
  MosaicBuilder(const BuildConfig& config, const CameraModel& camera, const LocalFrame& frame, const MosaicPlan& plan,
                TileStore* store, BuildHooks hooks = {});
  ~MosaicBuilder();

  // Offline builds: the whole survey, before the first Push. A tile is then
  // kept in the buffer while a frame among the next `lookahead_frames` will
  // be over it, so a survey line returning to it does not read it back.
  void Foresee(const std::vector<FrameSpec>& frames);
  // Queues a frame; blocks while the pipeline is full. Frames must come in acquisition order.
  void Push(const FrameSpec& frame);
  // Rejects a frame before it enters the pipeline (e.g. navigation problems).
  void Reject(const Rejection& rejection);
  // Blends everything queued, writes all tiles, overviews and metadata, commits.
  void Finish();

  const BuildStats& stats() const { return stats_; }
  const MosaicPlan& plan() const { return plan_; }

 private:
  struct Prepared {
    FrameSpec spec;
    FrameImage image;  // the frame, until it is warped; empty when rejected
    std::optional<WarpedFrame> warped;
    std::vector<TailPixel> tail;  // left out of `warped`; `image` stays for it
    std::optional<std::array<LatLon, 4>> footprint;
    std::string reject_field, reject_reason;
  };
  // A loaded frame waiting for its turn to be blended. A usable frame's warp
  // starts once the next usable frame is known (its neighbour for seams).
  struct Queued {
    Prepared prepared;
    std::vector<VehiclePose> neighbours;
    std::string problem;          // set by the warp job when the image cannot be decoded
    std::vector<TailPixel> tail;  // set by the warp job
    std::future<std::optional<WarpedFrame>> warp;
    // Loaded and checked, so it will be warped. (The warp job decodes rows
    // of the image meanwhile; its size, read here, does not change.)
    bool Usable() const { return !prepared.image.empty(); }
  };
  struct Slot {
    std::unique_ptr<TileAccumulator> accumulator;
    int last_frame = 0;
  };

  Prepared Load(const FrameSpec& spec) const;
  // Why a frame's attitude is too steep to map (footprint over
  // max_footprint_ratio times the nadir one), or nullopt.
  std::optional<std::string> TooSteep(const VehiclePose& pose, const std::array<LocalXY, 4>& corners) const;
  void TakeLoaded();  // oldest load -> queued_ (waits for it); starts the previous usable frame's warp
  void StartWarp(const std::shared_ptr<Queued>& q);
  // Blends queued frames, oldest first, while their warps are done; with
  // wait_for_one it first waits for the oldest.
  void ConsumeReady(bool wait_for_one);
  void Consume(Prepared prepared);
  void Paint(const WarpedFrame& warped);
  // Base tiles [x0, x1] x [y0, y1] under a box of global pixels (clipped to the zoom's tiles).
  std::array<int64_t, 4> TilesUnder(int64_t x0, int64_t y0, int64_t width, int64_t height) const;
  bool OverSoon(const TileId& id) const;  // a foreseen frame soon to come is over the tile
  void FinishTiles(bool all);
  void FinishTile(const TileId& id);
  void FlushBatch();
  void WriteMetadata(bool complete);
  cv::Mat ReadBack(const TileId& id);
  // Waiting tails: the pixels no frame has painted yet (in a tile still
  // being painted, or finished with its weights kept) are decoded, on the
  // pool, and painted; the others are dropped.
  void SettleTails(std::vector<PendingTails::Taken> taken);
  std::vector<TailPixel> Unpainted(const std::vector<TailPixel>& pixels) const;
  TileId BaseTileOf(int64_t x, int64_t y) const;  // of a global pixel at the base zoom
  void SettleDueTails();  // those that waited lookahead_frames, and the oldest over the memory share
  // The side-edge halves (FrameWarper::kTail* bits) where the frame's tail
  // is worth deferring (CoveredSides by the foreseen frames within the
  // look-ahead): elsewhere it would be decoded later anyway, after its rows
  // were read once.
  unsigned TailSides(const FrameSpec& spec) const;

  BuildConfig config_;
  CameraModel camera_;
  LocalFrame frame_;
  MosaicPlan plan_;
  TileStore* store_;
  BuildHooks hooks_;
  FrameWarper warper_;
  std::unique_ptr<ThreadPool> pool_;
  size_t pipeline_depth_ = 0;  // frames loading or queued before Push waits
  std::unique_ptr<TileWriter> writer_;
  std::unique_ptr<OverviewPyramid> pyramid_;
  std::deque<std::future<Prepared>> loading_;
  std::deque<std::shared_ptr<Queued>> queued_;  // loaded, in acquisition order
  std::shared_ptr<Queued> awaiting_next_;       // last usable frame, warp not started yet
  std::unordered_map<TileId, Slot, TileIdHash> buffer_;
  PendingTails tails_;
  bool defer_tails_ = false;  // set by Foresee (BuildConfig::defer_edge_tails)
  size_t buffer_bytes_ = 0;
  // Weights of finished base tiles (TileAccumulator::Weights), oldest
  // dropped first past a share of the memory cap.
  struct KeptWeights {
    cv::Mat weights;
    uint64_t stamp;  // which entry of finished_order_ is this one's
  };
  std::unordered_map<TileId, KeptWeights, TileIdHash> finished_weights_;
  std::deque<std::pair<TileId, uint64_t>> finished_order_;
  uint64_t finished_stamp_ = 0;
  size_t finished_weights_bytes_ = 0;
  // Foresee: for each base tile, the indices (FrameSpec::index, ascending)
  // of the frames whose box is over it; and the last index consumed.
  std::unordered_map<TileId, std::vector<int>, TileIdHash> foreseen_;
  struct ForeseenFrame {
    MapFootprint footprint;
    std::array<int64_t, 4> tiles;  // TilesUnder its box
  };
  std::vector<std::optional<ForeseenFrame>> foreseen_frames_;  // by frame index
  int last_index_ = -1;
  int consumed_ = 0;
  int track_seq_ = 0;
  int frame_id_offset_ = 0;  // ids of an appended mission's frames continue after the stored ones
  BuildStats stats_;
  std::chrono::steady_clock::time_point start_, last_flush_;
  double start_cpu_ = 0;
  int last_flush_frame_ = 0;
  bool finished_ = false;
};

// Peak resident memory of this process so far, bytes.
int64_t PeakRssBytes();
// CPU time this process has used so far (user + system, all threads), seconds.
double ProcessCpuSeconds();

}  // namespace seamap
