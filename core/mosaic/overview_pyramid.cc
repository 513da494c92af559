#include "core/mosaic/overview_pyramid.h"

#include <algorithm>
#include <map>
#include <vector>

namespace seamap {

cv::Mat ReduceTile2x(const cv::Mat& tile) {
  const int ch = tile.channels();  // colour channels + alpha
  const int colour = ch - 1;
  cv::Mat out(tile.rows / 2, tile.cols / 2, tile.type(), cv::Scalar::all(0));
  for (int y = 0; y < out.rows; ++y) {
    const uint8_t* r0 = tile.ptr<uint8_t>(2 * y);
    const uint8_t* r1 = tile.ptr<uint8_t>(2 * y + 1);
    uint8_t* d = out.ptr<uint8_t>(y);
    for (int x = 0; x < out.cols; ++x, d += ch) {
      const uint8_t* p[4] = {r0 + 2 * x * ch, r0 + (2 * x + 1) * ch, r1 + 2 * x * ch, r1 + (2 * x + 1) * ch};
      int alpha_sum = p[0][colour] + p[1][colour] + p[2][colour] + p[3][colour];
      if (alpha_sum == 0) continue;
      if (alpha_sum == 4 * 255) {  // all four painted (most pixels): the weighted mean below, without a division
        for (int c = 0; c < colour; ++c) d[c] = static_cast<uint8_t>((p[0][c] + p[1][c] + p[2][c] + p[3][c] + 2) >> 2);
        d[colour] = 255;
        continue;
      }
      for (int c = 0; c < colour; ++c) {
        int s = p[0][c] * p[0][colour] + p[1][c] * p[1][colour] + p[2][c] * p[2][colour] + p[3][c] * p[3][colour];
        d[c] = static_cast<uint8_t>((s + alpha_sum / 2) / alpha_sum);
      }
      d[colour] = static_cast<uint8_t>((alpha_sum + 2) / 4);
    }
  }
  return out;
}

OverviewPyramid::OverviewPyramid(TileWriter* writer, int tile_size, int channels, int min_zoom, int base_zoom,
                                 size_t memory_cap_bytes)
    : writer_(writer),
      tile_size_(tile_size),
      channels_(channels),
      min_zoom_(min_zoom),
      base_zoom_(base_zoom),
      cap_bytes_(memory_cap_bytes) {}

OverviewPyramid::Entry& OverviewPyramid::Load(const TileId& id) {
  auto it = tiles_.find(id);
  if (it != tiles_.end()) {
    lru_.splice(lru_.begin(), lru_, it->second.lru);
    return it->second;
  }
  Entry e;
  auto stored = writer_->Read(id);
  if (stored && stored->rows == tile_size_ && stored->cols == tile_size_) {
    e.tile = WithColourChannels(*stored, channels_);
  } else {
    e.tile = cv::Mat(tile_size_, tile_size_, CV_8UC(channels_ + 1), cv::Scalar::all(0));
  }
  lru_.push_front(id);
  e.lru = lru_.begin();
  bytes_ += e.tile.total() * e.tile.elemSize();
  return tiles_.emplace(id, std::move(e)).first->second;
}

void OverviewPyramid::UpdateChild(const TileId& child, const cv::Mat& tile) {
  if (child.z <= min_zoom_) return;
  Entry& parent = Load(child.Parent());
  const int half = tile_size_ / 2;
  cv::Mat quadrant = parent.tile(cv::Rect((child.x & 1) * half, (child.y & 1) * half, half, half));
  ReduceTile2x(tile).copyTo(quadrant);
  parent.dirty = true;
}

void OverviewPyramid::Flush() {
  for (int z = base_zoom_ - 1; z >= min_zoom_; --z) {
    std::vector<TileId> dirty;
    for (auto& [id, e] : tiles_)
      if (id.z == z && e.dirty) dirty.push_back(id);
    std::sort(dirty.begin(), dirty.end());
    for (const TileId& id : dirty) {
      Entry& e = tiles_.at(id);
      e.dirty = false;
      // The writer keeps a reference while encoding; later changes go to a copy.
      cv::Mat snapshot = e.tile.clone();
      writer_->Submit(id, snapshot);
      UpdateChild(id, snapshot);
    }
  }
  EvictClean();
}

void OverviewPyramid::EvictClean() {
  auto it = lru_.end();
  while (bytes_ > cap_bytes_ && it != lru_.begin()) {
    --it;
    auto found = tiles_.find(*it);
    if (found->second.dirty) continue;
    bytes_ -= found->second.tile.total() * found->second.tile.elemSize();
    tiles_.erase(found);
    it = lru_.erase(it);
  }
}

int64_t OverviewPyramid::DirtyCount() const {
  int64_t n = 0;
  for (const auto& [id, e] : tiles_) n += e.dirty;
  return n;
}

}  // namespace seamap
