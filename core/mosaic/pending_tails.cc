#include "core/mosaic/pending_tails.h"

#include <algorithm>
#include <iterator>
#include <utility>

namespace seamap {

size_t PendingTails::pixels() const {
  size_t n = 0;
  for (const Frame& f : frames_) n += f.pixels.size();
  return n;
}

void PendingTails::Add(int order, FrameImage image, std::vector<TailPixel> pixels) {
  if (pixels.empty()) return;
  Frame f;
  f.order = order;
  f.image = std::make_shared<FrameImage>(std::move(image));
  f.pixels = std::move(pixels);
  f.bounds = TailBounds(f.pixels);
  f.bytes = f.image->Bytes() + f.pixels.size() * sizeof(TailPixel);
  bytes_ += f.bytes;
  frames_.push_back(std::move(f));
}

std::vector<PendingTails::Taken> PendingTails::TakeIn(int64_t x0, int64_t y0, int64_t x1, int64_t y1) {
  std::vector<Taken> out;
  for (size_t i = 0; i < frames_.size();) {
    Frame& f = frames_[i];
    if (f.bounds[2] <= x0 || f.bounds[0] >= x1 || f.bounds[3] <= y0 || f.bounds[1] >= y1) {
      ++i;
      continue;
    }
    const auto outside = [&](const TailPixel& p) { return p.x < x0 || p.x >= x1 || p.y < y0 || p.y >= y1; };
    const auto split = std::stable_partition(f.pixels.begin(), f.pixels.end(), outside);
    if (split != f.pixels.end()) {
      out.push_back({f.image, std::vector<TailPixel>(split, f.pixels.end())});
      f.pixels.erase(split, f.pixels.end());
    }
    if (!f.pixels.empty()) {
      ++i;
      continue;
    }
    bytes_ -= f.bytes;
    frames_.erase(frames_.begin() + static_cast<std::ptrdiff_t>(i));
  }
  return out;
}

void PendingTails::PopFront(std::vector<Taken>* out) {
  Frame& f = frames_.front();
  out->push_back({std::move(f.image), std::move(f.pixels)});
  bytes_ -= f.bytes;
  frames_.pop_front();
}

std::vector<PendingTails::Taken> PendingTails::TakeUpTo(int order) {
  std::vector<Taken> out;
  while (!frames_.empty() && frames_.front().order <= order) PopFront(&out);
  return out;
}

std::vector<PendingTails::Taken> PendingTails::TakeOldest() {
  std::vector<Taken> out;
  if (!frames_.empty()) PopFront(&out);
  return out;
}

std::vector<TailPixel> PendingTails::TakeFrame(const std::shared_ptr<FrameImage>& image) {
  const auto it = std::find_if(frames_.begin(), frames_.end(), [&](const Frame& f) { return f.image == image; });
  if (it == frames_.end()) return {};
  std::vector<TailPixel> pixels = std::move(it->pixels);
  bytes_ -= it->bytes;
  frames_.erase(it);
  return pixels;
}

std::vector<PendingTails::Taken> PendingTails::TakeAll() {
  std::vector<Taken> out;
  while (!frames_.empty()) PopFront(&out);
  return out;
}

}  // namespace seamap
