#pragma once
// Painting a frame's tail later: the side-edge pixels FrameWarper::Warp left
// out unsampled, so that the JPEG rows they need were not decoded (see Warp
// and MosaicBuilder).
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "core/mosaic/frame_image.h"
#include "core/mosaic/frame_warper.h"

namespace seamap {

// The global pixels around the tail pixels: {x0, y0, x1, y1}, spanning
// [x0, x1) x [y0, y1) (all 0 for none).
std::array<int64_t, 4> TailBounds(const std::vector<TailPixel>& pixels);

// Tail pixels sampled (bilinearly, as Warp samples) from `image`, which has
// the rows they need decoded, as a frame to blend. No pixels: an empty frame.
WarpedFrame SampleTail(const std::vector<TailPixel>& pixels, const cv::Mat& image);

// Decodes the rows the pixels need from `image`, samples them and releases
// the decoded rows again. One image is used by one job at a time. Throws
// InputError, naming the file, if the JPEG data breaks off before them.
WarpedFrame DecodeTail(FrameImage& image, const std::vector<TailPixel>& pixels);

}  // namespace seamap
