#include "core/mosaic/mosaic_builder.h"

#include <algorithm>
#include <cstdio>

#include <opencv2/core.hpp>

#include "core/mission/mission_metadata.h"
#include "core/util/error.h"
#include "core/util/process_stats.h"

namespace seamap {
namespace {

WarpOptions WarpOptionsOf(const BuildConfig& config, const MosaicPlan& plan) {
  WarpOptions o;
  o.channels = plan.channels;
  o.feather_power = config.blend.feather_power;
  o.seam_band = config.blend.blend_all_overlaps ? 0.0 : config.blend.seam_band;
  o.nadir_seams = config.blend.nadir_seams;
  return o;
}

TileBufferOptions BufferOptionsOf(const BuildConfig& config, const MosaicPlan& plan) {
  const MemoryBudget budget = MemoryBudget::Of(config.buffer.memory_cap_mb);
  TileBufferOptions o;
  o.zoom = plan.base_zoom;
  o.tile_size = config.map.tile_size;
  o.channels = plan.channels;
  o.linger_frames = config.buffer.linger_frames;
  o.lookahead_frames = config.buffer.lookahead_frames;
  o.memory_bytes = budget.tile_buffer_bytes;
  o.finished_weights_bytes = budget.finished_weights_bytes;
  return o;
}

MapDescription DescriptionOf(const BuildConfig& config, const MosaicPlan& plan) {
  MapDescription d;
  d.name = config.map.name;
  d.attribution = config.map.attribution;
  d.format = TileExtension(config.map.encoding.format);
  d.tile_size = config.map.tile_size;
  d.channels = plan.channels;
  d.min_zoom = plan.min_zoom;
  d.base_zoom = plan.base_zoom;
  d.gsd_m = plan.gsd_m;
  return d;
}

}  // namespace

MosaicBuilder::MosaicBuilder(const BuildConfig& config, const CameraModel& camera, const LocalFrame& frame,
                             const MosaicPlan& plan, TileStore* store, BuildHooks hooks, const BuildStart& start)
    : config_(config),
      plan_(plan),
      store_(store),
      hooks_(std::move(hooks)),
      warper_(camera, frame, plan.base_zoom, config.map.tile_size, WarpOptionsOf(config, plan), hooks_.surface),
      pool_(std::make_unique<ThreadPool>(config.threads)),
      writer_(std::make_unique<TileWriter>(store, pool_.get(), config.map.encoding, hooks_.tile_consumers)),
      pyramid_(std::make_unique<OverviewPyramid>(writer_.get(), config.map.tile_size, plan.channels, plan.min_zoom,
                                                 plan.base_zoom,
                                                 MemoryBudget::Of(config.buffer.memory_cap_mb).overview_bytes)),
      buffer_(
          BufferOptionsOf(config, plan), &forecast_,
          [this](const TileId& id, const cv::Mat& tile) { Finished(id, tile); },
          [this](const TileId& id) { return writer_->ReadToPaint(id, plan_.channels, config_.map.tile_size); }),
      recorder_(store, frame, DescriptionOf(config, plan)),
      mode_(start),
      start_(std::chrono::steady_clock::now()),
      last_flush_(start_),
      start_cpu_(ProcessCpuSeconds()) {
  // We parallelise across frames and tiles; OpenCV's own threads inside each
  // call would only compete with ours on a small on-board CPU.
  cv::setNumThreads(1);
  // Up to eight frames in flight per pool thread: frames finish out of order
  // and tile encodes come in bursts, and with two per thread plus four the
  // cores sat idle for a fifth of a build. A waiting frame may hold its
  // decoded image (not JPEG, or enhanced), so the depth also stays within the
  // frames' memory share, but not below two per thread plus four.
  FramePipelineOptions pipeline;
  pipeline.channels = plan.channels;
  pipeline.sixteen_bit_white = config.frames.sixteen_bit_white;
  pipeline.max_footprint_ratio = config.frames.max_footprint_ratio;
  pipeline.max_image_pixels = config.frames.max_image_pixels;
  pipeline.max_paint_bytes = FramePaintLimitBytes(plan, camera, config.map.tile_size, config.buffer.memory_cap_mb);
  pipeline.preprocess = hooks_.preprocess;
  const size_t frame_bytes = static_cast<size_t>(camera.width) * camera.height * plan.channels + 1;
  const size_t threads = static_cast<size_t>(pool_->size());
  pipeline.depth = std::clamp(MemoryBudget::Of(config.buffer.memory_cap_mb).frames_bytes / frame_bytes, 2 * threads + 4,
                              8 * threads);
  pipeline_ = std::make_unique<FramePipeline>(&warper_, pool_.get(), std::move(pipeline),
                                              [this](PlacedFrame placed) { Consume(std::move(placed)); });
  if (auto state = ReadMissionMetadata(*store_).state) previous_state_ = *state;
  // checkpoint_seconds 0: none (a resumed build still reads the one it resumes from).
  if (mode_.checkpoints && store_->Checkpoints() && (config.buffer.checkpoint_seconds > 0 || mode_.resume))
    checkpointer_ = std::make_unique<BuildCheckpointer>(store_->Checkpoints(), &buffer_, &forecast_, pool_.get(),
                                                        config.map.tile_size, plan.channels);
  last_checkpoint_ = start_;
  if (mode_.resume) {
    Resume();
    return;
  }
  recorder_.WriteState("building", 0, 0);
  if (checkpointer_)
    WriteCheckpoint(previous_state_ == "complete");  // the start; an append keeps the map as it was until it ends
  else
    store_->Flush();
}

MosaicBuilder::~MosaicBuilder() {
  // Let queued work drain before members go away, and stop the pool while
  // the writer its jobs use still exists.
  pipeline_.reset();
  pool_.reset();
  if (!finished_ && checkpointer_) Abandon();
}

nlohmann::json MosaicBuilder::Settings(const BuildConfig& c, const MosaicPlan& plan, bool enhanced) {
  nlohmann::json settings = {
      {"tile_size", c.map.tile_size},
      {"base_zoom", plan.base_zoom},
      {"min_zoom", plan.min_zoom},
      {"channels", plan.channels},
      {"tile_format", TileExtension(c.map.encoding.format)},
      {"png_level", c.map.encoding.png_level},
      {"jpeg_quality", c.map.encoding.jpeg_quality},
      {"webp_quality", c.map.encoding.webp_quality},
      {"feather_power", c.blend.feather_power},
      {"seam_band", c.blend.seam_band},
      {"blend_all_overlaps", c.blend.blend_all_overlaps},
      {"linger_frames", c.buffer.linger_frames},
      {"lookahead_frames", c.buffer.lookahead_frames},
      {"memory_cap_mb", c.buffer.memory_cap_mb},
      {"max_footprint_ratio", c.frames.max_footprint_ratio},
      {"sixteen_bit_white", c.frames.sixteen_bit_white},
      {"enhance", enhanced ? c.enhance.value_or(nlohmann::json("on")) : nlohmann::json(nullptr)}};
  // Only when set: checkpoints of flat builds stay as they were.
  if (c.terrain.enabled())
    settings["terrain"] = c.terrain.file.empty() ? nlohmann::json(true) : nlohmann::json(c.terrain.file);
  return settings;
}

void MosaicBuilder::WriteCheckpoint(bool keep_start) {
  const auto began = std::chrono::steady_clock::now();
  BuildProgress p;
  p.frame_index = last_index_;
  p.handover_index = handover_index_;
  p.frames_total = mode_.frames_total;
  p.consumed = consumed_;
  p.frame_id_offset = recorder_.frame_id_offset();
  p.track_seq = recorder_.next_track_seq();
  p.frames_used = stats_.frames_used;
  p.tiles_written = writer_->tiles_written();
  p.tile_bytes = writer_->bytes_written();
  p.readbacks = buffer_.readbacks();
  p.previous_state = previous_state_;
  p.command = mode_.command;
  p.settings = Settings(config_, plan_, static_cast<bool>(hooks_.preprocess));
  // Frames after the last one consumed (ids from here on) are newer than the checkpoint.
  checkpointer_->Write(p, int64_t{p.frame_id_offset} + last_index_ + 1, p.track_seq, keep_start);
  checkpoint_index_ = last_index_;
  last_checkpoint_ = std::chrono::steady_clock::now();
  ++stats_.checkpoints;
  stats_.checkpoint_seconds += std::chrono::duration<double>(last_checkpoint_ - began).count();
}

void MosaicBuilder::Resume() {
  const std::optional<BuildProgress> progress = checkpointer_ ? checkpointer_->Read() : std::nullopt;
  if (!progress) throw InputError("", 0, "--resume", "the map has no checkpoint to resume from");
  const nlohmann::json now = Settings(config_, plan_, static_cast<bool>(hooks_.preprocess));
  for (const auto& [key, was] : progress->settings.items()) {
    const nlohmann::json is = now.value(key, nlohmann::json(nullptr));
    if (is != was)
      throw InputError("", 0, key,
                       "was " + was.dump() + " when the build began and is " + is.dump() +
                           " now: resume with the same arguments and config (or --overwrite to start again)");
  }
  store_->Checkpoints()->RollBackToCheckpoint();  // tiles, frames and track as they were at the checkpoint
  checkpointer_->Restore(*progress);
  consumed_ = last_flush_frame_ = progress->consumed;
  last_index_ = resume_index_ = checkpoint_index_ = progress->frame_index;
  handover_index_ = progress->handover_index;
  // The last frame that reached the warp goes through the pipeline again
  // (not painted): the next frame hands pixels over to it as it did.
  prime_from_ = handover_index_ >= 0 ? handover_index_ : resume_index_ + 1;
  previous_state_ = progress->previous_state;
  std::vector<FrameRecord> recorded;
  for (FrameRecord& f : store_->Records().Frames())
    if (f.id >= progress->frame_id_offset && f.id <= progress->frame_id_offset + progress->frame_index)
      recorded.push_back(std::move(f));
  recorder_.Resume(progress->frame_id_offset, progress->track_seq, recorded);
  stats_.frames_seen = progress->consumed;
  stats_.frames_used = progress->frames_used;
  for (const FrameRecord& f : recorded)
    if (f.status != "used") stats_.rejections.push_back({f.image_path, 0, "", f.status});
  writer_->Resume(progress->tiles_written, progress->tile_bytes, store_->TileIds());
  recorder_.WriteState("building", stats_.frames_used, static_cast<int>(stats_.rejections.size()));
  store_->Flush();
}

void MosaicBuilder::Abandon() {
  // The map was complete before this build (a failed --append, resumed or
  // not): return it to that, tiles, frames, track and state. Any other
  // failed build stays interrupted, to be resumed.
  if (previous_state_ != "complete") return;
  try {
    if (!store_->Checkpoints()->RollBackToStart()) return;
    MissionMetadata restored;
    restored.state = previous_state_;
    WriteMissionMetadata(store_, restored);
    store_->Checkpoints()->DropCheckpoint();
    store_->Flush();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "warning: cannot return the map to its state before this build: %s\n", e.what());
  }
}

void MosaicBuilder::Foresee(const std::vector<FrameSpec>& frames) {
  if (config_.buffer.lookahead_frames <= 0) return;
  // Outlines on the pool (each is a few dozen projections), tiles in order.
  // Frames the pipeline will refuse (too steep: their box can span
  // thousands of tiles) are left out.
  const SeabedProjection& projection = warper_.projection();
  using Outline = std::optional<SeabedProjection::MapOutline>;
  std::vector<std::future<Outline>> outlines;
  outlines.reserve(frames.size());
  for (const FrameSpec& f : frames)
    outlines.push_back(pool_->Submit([this, &projection, &f]() -> Outline {
      const auto corners = projection.GroundCorners(f.pose);
      if (!corners || TooSteep(projection.camera(), f.pose, *corners, config_.frames.max_footprint_ratio))
        return std::nullopt;
      Outline outline = warper_.Outline(f.pose);
      if (outline &&
          FramePaintBytes(static_cast<double>(outline->box[2]), static_cast<double>(outline->box[3]),
                          config_.map.tile_size, plan_.channels) >
              FramePaintLimitBytes(plan_, projection.camera(), config_.map.tile_size, config_.buffer.memory_cap_mb))
        return std::nullopt;  // refused too (TooLargeToPaint)
      return outline;
    }));
  for (size_t i = 0; i < frames.size(); ++i) {
    const Outline outline = outlines[i].get();
    if (!outline) continue;
    const auto& b = outline->box;
    forecast_.Add(frames[i].index, plan_.base_zoom,
                  TilesUnder(plan_.base_zoom, config_.map.tile_size, b[0], b[1], b[2], b[3]));
  }
}

void MosaicBuilder::Push(const FrameSpec& frame, const cv::Mat& decoded) {
  if (frame.index >= prime_from_) pipeline_->Push(frame, decoded);
}

void MosaicBuilder::Reject(const Rejection& rejection) {
  ++stats_.frames_seen;
  stats_.rejections.push_back(rejection);
}

void MosaicBuilder::Consume(PlacedFrame placed) {
  if (placed.spec.index <= resume_index_) return;  // done before the checkpoint: a handover partner only
  if (placed.handover) handover_index_ = placed.spec.index;
  ++stats_.frames_seen;
  ++consumed_;  // this frame's number: tiles it paints are stamped with it
  last_index_ = placed.spec.index;
  if (placed.warped) {
    buffer_.Paint(*placed.warped, consumed_);
    ++stats_.frames_used;
  } else {
    const FrameSpec& s = placed.spec;
    stats_.rejections.push_back({s.image_path, s.nav_line, placed.reject_field, placed.reject_reason});
  }
  const auto [record, point] = recorder_.Record(placed);
  if (hooks_.on_frame) hooks_.on_frame(record, point);

  buffer_.FinishDue(consumed_, last_index_);
  const auto now = std::chrono::steady_clock::now();
  if (consumed_ - last_flush_frame_ >= config_.buffer.batch_frames &&
      std::chrono::duration<double>(now - last_flush_).count() >= config_.buffer.batch_seconds) {
    FlushBatch();
    last_flush_frame_ = consumed_;
    last_flush_ = now;
  }
}

void MosaicBuilder::Finished(const TileId& id, const cv::Mat& tile) {
  writer_->Submit(id, tile);
  pyramid_->UpdateChild(id, tile);
}

void MosaicBuilder::FlushBatch() {
  if (config_.buffer.live_tiles) {
    // The unfinished tiles as painted so far; their final version replaces
    // them (and their overview quadrants) when they are finished.
    buffer_.ForEachUnfinished([this](const TileId& id, const cv::Mat& tile) {
      writer_->Submit(id, tile, /*final=*/false);
      pyramid_->UpdateChild(id, tile);
    });
  }
  pyramid_->Flush();
  recorder_.WriteState("building", stats_.frames_used, static_cast<int>(stats_.rejections.size()));
  writer_->Flush();
  UpdateWriteStats();  // live progress for a replay
  if (checkpointer_ && config_.buffer.checkpoint_seconds > 0 &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint_).count() >=
          config_.buffer.checkpoint_seconds)
    WriteCheckpoint();
}

void MosaicBuilder::UpdateWriteStats() {
  stats_.tiles_written = writer_->tiles_written();
  stats_.tile_bytes = writer_->bytes_written();
  stats_.readbacks = buffer_.readbacks();
}

void MosaicBuilder::Finish() {
  if (finished_) return;
  pipeline_->Finish();
  buffer_.FinishAll();
  pyramid_->Flush();
  writer_->Flush();
  UpdateWriteStats();
  stats_.tiles_per_zoom = writer_->distinct_tiles_per_zoom();
  recorder_.WriteState("complete", stats_.frames_used, static_cast<int>(stats_.rejections.size()));
  if (checkpointer_) store_->Checkpoints()->DropCheckpoint();  // in the same transaction as "complete"
  store_->Flush();
  stats_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  stats_.cpu_seconds = ProcessCpuSeconds() - start_cpu_;
  finished_ = true;
}

}  // namespace seamap
