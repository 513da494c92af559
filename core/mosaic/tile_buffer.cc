#include "core/mosaic/tile_buffer.h"

#include <algorithm>
#include <vector>

namespace seamap {
namespace {

size_t BytesOf(const cv::Mat& m) {
  return m.total() * m.elemSize();
}

}  // namespace

TileBuffer::TileBuffer(const TileBufferOptions& options, const TileForecast* forecast, Finished finished,
                       ReadBack read_back)
    : options_(options), forecast_(forecast), finished_(std::move(finished)), read_back_(std::move(read_back)) {}

void TileBuffer::Touch(const WarpedFrame& frame, int frame_number) {
  const TileRange over =
      TilesUnder(options_.zoom, options_.tile_size, frame.box_x0, frame.box_y0, frame.box_width, frame.box_height);
  for (int64_t ty = over.y0; ty <= over.y1; ++ty)
    for (int64_t tx = over.x0; tx <= over.x1; ++tx) {
      auto it = tiles_.find(TileId{options_.zoom, WrapTileX(options_.zoom, tx), static_cast<int>(ty)});
      if (it != tiles_.end()) it->second.last_frame = frame_number;
    }
}

void TileBuffer::Paint(const WarpedFrame& frame, int frame_number) {
  Touch(frame, frame_number);
  const int64_t ts = options_.tile_size;
  const TileRange painted =
      TilesUnder(options_.zoom, options_.tile_size, frame.x0, frame.y0, frame.pixels.cols, frame.pixels.rows);
  for (int64_t ty = painted.y0; ty <= painted.y1; ++ty) {
    for (int64_t tx = painted.x0; tx <= painted.x1; ++tx) {
      // Tiles inside the painted box that the frame leaves empty (it is
      // rotated, or hands them to a neighbour) are not started.
      const int64_t x_begin = std::max(tx * ts, frame.x0), y_begin = std::max(ty * ts, frame.y0);
      const int64_t x_end = std::min((tx + 1) * ts, frame.x0 + frame.pixels.cols);
      const int64_t y_end = std::min((ty + 1) * ts, frame.y0 + frame.pixels.rows);
      const cv::Rect roi(static_cast<int>(x_begin - frame.x0), static_cast<int>(y_begin - frame.y0),
                         static_cast<int>(x_end - x_begin), static_cast<int>(y_end - y_begin));
      if (!PaintsAny(frame, roi)) continue;
      // Past the antimeridian, column tx is tile `wrapped`, a world away.
      const int wrapped = WrapTileX(options_.zoom, tx);
      const TileId id{options_.zoom, wrapped, static_cast<int>(ty)};
      Slot& slot = Open(id);
      slot.accumulator->Blend(frame, (wrapped - tx) * ts);
      slot.last_frame = frame_number;
      changed_tiles_.insert(id);
    }
  }
}

TileBuffer::Slot& TileBuffer::Open(const TileId& id) {
  auto it = tiles_.find(id);
  if (it != tiles_.end()) return it->second;
  Slot slot;
  const int ts = options_.tile_size;
  slot.accumulator = std::make_unique<TileAccumulator>(ts, options_.channels, int64_t{id.x} * ts, int64_t{id.y} * ts);
  // Painted before: continue from what was written, with the weights it had when they are still known.
  auto kept = kept_.find(id);
  const cv::Mat previous = read_back_(id);
  if (!previous.empty()) {
    slot.accumulator->Seed(previous, kept != kept_.end() ? kept->second.weights : cv::Mat());
    ++readbacks_;
  }
  if (kept != kept_.end()) {  // the accumulator has them now
    kept_bytes_ -= kept->second.bytes;
    kept_.erase(kept);
    changed_kept_.insert(id);
  }
  bytes_ += slot.accumulator->Bytes();
  return tiles_.emplace(id, std::move(slot)).first->second;
}

void TileBuffer::FinishDue(int frame_number, int frame_index) {
  std::vector<TileId> done;
  std::vector<std::pair<int, TileId>> by_age;  // the tiles kept
  for (const auto& [id, slot] : tiles_) {
    const bool missed = frame_number - slot.last_frame >= options_.linger_frames;
    const bool coming_back = forecast_ && forecast_->OverSoon(id, frame_index, options_.lookahead_frames);
    if (missed && !coming_back)
      done.push_back(id);
    else
      by_age.push_back({slot.last_frame, id});
  }
  // Over the memory budget: the least recently painted tiles go first.
  size_t bytes = bytes_;  // what stays once `done` is finished
  for (const TileId& id : done) bytes -= tiles_.at(id).accumulator->Bytes();
  if (bytes > options_.memory_bytes) {
    std::sort(by_age.begin(), by_age.end());
    for (const auto& [age, id] : by_age) {
      if (bytes <= options_.memory_bytes) break;
      bytes -= tiles_.at(id).accumulator->Bytes();
      done.push_back(id);
    }
  }
  std::sort(done.begin(), done.end());
  for (const TileId& id : done) Finish(id);
}

void TileBuffer::FinishAll() {
  std::vector<TileId> done;
  for (const auto& [id, slot] : tiles_) done.push_back(id);
  std::sort(done.begin(), done.end());
  for (const TileId& id : done) Finish(id);
}

void TileBuffer::Finish(const TileId& id) {
  auto it = tiles_.find(id);
  const cv::Mat tile = it->second.accumulator->Finalize();
  cv::Mat weights = it->second.accumulator->Weights();
  const size_t weight_bytes = BytesOf(weights);
  KeepWeights(id, std::move(weights), weight_bytes);
  bytes_ -= it->second.accumulator->Bytes();
  tiles_.erase(it);
  changed_tiles_.insert(id);
  finished_(id, tile);
}

void TileBuffer::KeepWeights(const TileId& id, cv::Mat weights, size_t bytes) {
  if (auto old = kept_.find(id); old != kept_.end()) kept_bytes_ -= old->second.bytes;
  kept_bytes_ += bytes;
  kept_[id] = {std::move(weights), ++kept_stamp_, bytes};
  kept_order_.push_back({id, kept_stamp_});
  changed_kept_.insert(id);
  while (kept_bytes_ > options_.finished_weights_bytes && !kept_order_.empty()) {
    const auto [oldest_id, stamp] = kept_order_.front();
    kept_order_.pop_front();
    auto oldest = kept_.find(oldest_id);
    if (oldest == kept_.end() || oldest->second.stamp != stamp) continue;  // superseded
    kept_bytes_ -= oldest->second.bytes;
    kept_.erase(oldest);
    changed_kept_.insert(oldest_id);
  }
}

void TileBuffer::ForEachUnfinished(const std::function<void(const TileId&, const cv::Mat&)>& visit) const {
  for (const auto& [id, slot] : tiles_) visit(id, slot.accumulator->Finalize());
}

TileBuffer::Changes TileBuffer::TakeChanges() {
  Changes c;
  c.tiles.assign(changed_tiles_.begin(), changed_tiles_.end());
  c.kept.assign(changed_kept_.begin(), changed_kept_.end());
  std::sort(c.tiles.begin(), c.tiles.end());
  std::sort(c.kept.begin(), c.kept.end());
  changed_tiles_.clear();
  changed_kept_.clear();
  return c;
}

const TileAccumulator* TileBuffer::Unfinished(const TileId& id) const {
  auto it = tiles_.find(id);
  return it == tiles_.end() ? nullptr : it->second.accumulator.get();
}

std::vector<std::pair<TileId, int>> TileBuffer::LastFrames() const {
  std::vector<std::pair<TileId, int>> out;
  for (const auto& [id, slot] : tiles_) out.push_back({id, slot.last_frame});
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::pair<TileId, uint64_t>> TileBuffer::KeptOrder() const {
  std::vector<std::pair<TileId, uint64_t>> out;
  for (const auto& [id, k] : kept_) out.push_back({id, k.stamp});
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  return out;
}

const cv::Mat* TileBuffer::Kept(const TileId& id) const {
  auto it = kept_.find(id);
  return it == kept_.end() ? nullptr : &it->second.weights;
}

void TileBuffer::RestoreTile(const TileId& id, int last_frame, const cv::Mat& sums, const cv::Mat& weight_sums) {
  const int ts = options_.tile_size;
  Slot slot;
  slot.accumulator = std::make_unique<TileAccumulator>(ts, options_.channels, int64_t{id.x} * ts, int64_t{id.y} * ts);
  slot.accumulator->Restore(sums, weight_sums);
  slot.last_frame = last_frame;
  bytes_ += slot.accumulator->Bytes();
  tiles_[id] = std::move(slot);
}

void TileBuffer::RestoreKept(const TileId& id, uint64_t stamp, cv::Mat weights) {
  // Restored oldest first: the budget drops the same ones as the build that saved them would have.
  const size_t bytes = static_cast<size_t>(options_.tile_size) * options_.tile_size * sizeof(uint16_t);
  kept_bytes_ += bytes;
  kept_[id] = {std::move(weights), stamp, bytes};
  kept_order_.push_back({id, stamp});
  kept_stamp_ = std::max(kept_stamp_, stamp);
}

}  // namespace seamap
