#pragma once
// Frames' side-edge tails (FrameWarper::Warp's `tail`) waiting to be settled.
// A tail is taken tile by tile when its tiles are finished, or whole when it
// has waited long enough: by then another survey line has usually painted
// its pixels, and a frame whose tail is all covered never decodes the rows
// below its handover band (and only skips those above it). Holds each
// waiting frame's compressed image.
#include <array>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <vector>

#include "core/mosaic/frame_image.h"
#include "core/mosaic/frame_tail.h"
#include "core/mosaic/frame_warper.h"

namespace seamap {

class PendingTails {
 public:
  // Tail pixels taken out of the set, with their frame's image (shared with
  // the pixels of that frame still waiting).
  struct Taken {
    std::shared_ptr<FrameImage> image;
    std::vector<TailPixel> pixels;
  };

  // `order` grows with each frame added (the builder's frame count).
  void Add(int order, FrameImage image, std::vector<TailPixel> pixels);
  // The pixels inside [x0, x1) x [y0, y1) (global pixels), oldest frame first.
  std::vector<Taken> TakeIn(int64_t x0, int64_t y0, int64_t x1, int64_t y1);
  // Every pixel of the frames added with order <= `order`, oldest first.
  std::vector<Taken> TakeUpTo(int order);
  // Every pixel of the oldest frame (none when empty).
  std::vector<Taken> TakeOldest();
  std::vector<Taken> TakeAll();
  // The pixels still waiting of the frame with this image.
  std::vector<TailPixel> TakeFrame(const std::shared_ptr<FrameImage>& image);

  bool empty() const { return frames_.empty(); }
  size_t frames() const { return frames_.size(); }
  size_t pixels() const;
  // Compressed images and pixel lists held.
  size_t bytes() const { return bytes_; }

 private:
  struct Frame {
    int order = 0;
    std::shared_ptr<FrameImage> image;
    std::vector<TailPixel> pixels;
    std::array<int64_t, 4> bounds{};  // TailBounds of the pixels (not narrowed as pixels are taken)
    size_t bytes = 0;
  };
  void PopFront(std::vector<Taken>* out);

  std::deque<Frame> frames_;  // oldest first
  size_t bytes_ = 0;
};

}  // namespace seamap
