#pragma once
// Places one frame on the map. Every map pixel (Web Mercator global pixels at
// the base zoom) inside the frame's box is traced back to the raw image
// (SeabedProjection: inverse seabed homography, then the lens model), given
// its blending weight (blend_rule.h: feather tent and handover to the
// previous and next frames) and, where the frame keeps it, sampled
// bilinearly from the raw frame (no separate undistortion pass).
//
// Warp runs four passes over the frame's box:
//   1. map    the mapping from box pixels to this frame's and its neighbours'
//             raw images, exact on a grid and interpolated between (MappingGrid);
//   2. weigh  each pixel's weight, block row by block row, skipping blocks
//             the frame clearly leaves to its neighbours; the kept pixels go
//             to a canvas (PaintCanvas) and the raw rows they need are noted;
//   3. sample the kept pixels from the raw frame, which by then needs only
//             those rows decoded (a JPEG kept compressed decodes a band);
//   4. cut    the painted part out of the canvas (WarpedFrame).
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/geo/local_frame.h"
#include "core/mosaic/blend_rule.h"
#include "core/mosaic/row_kernels.h"
#include "core/mosaic/seabed_projection.h"
#include "core/mosaic/surface_projection.h"
#include "core/mosaic/warped_frame.h"

namespace seamap {

struct WarpOptions {
  int channels = 1;            // 1: gray mosaic, 3: colour (BGR)
  double feather_power = 1.0;  // weight = tent^power
  // Share (0, 1] of the way from the midpoint to a neighbour's centre over
  // which a frame hands pixels over (blend_rule.h); 0: no handover, every
  // overlapping frame blends everywhere.
  double seam_band = 0;
  int grid_step = 16;  // map pixels between exact evaluations of the mapping, 1..64
  // The same over a height model: the mapping follows the relief (and
  // occlusion's edges), so it is evaluated more densely. Measured on 0.3 m
  // rms relief (docs/TERRAIN.md): p90 offset 0.14 / 0.16 / 0.23 px at
  // steps 4 / 8 / 16, for 6.2 / 2.2 / 1.3 times a flat build's CPU.
  int surface_grid_step = 8;
  // Over a surface: seams by the rays' angle to the vertical (blend_rule.h).
  bool nadir_seams = true;
  KernelPath kernels = KernelPath::kFast;  // the reference path is for tests and measurements
};

class FrameWarper {
 public:
  // surface: the seabed's height model (a true orthophoto, surface_projection.h);
  // null: the plane at each frame's altitude.
  FrameWarper(const CameraModel& camera, const LocalFrame& frame, int zoom, int tile_size, const WarpOptions& options,
              std::shared_ptr<const HeightGrid> surface = nullptr);

  const SeabedProjection& projection() const { return projection_; }
  // The frame's box on the map, on the surface when there is one.
  std::optional<SeabedProjection::MapOutline> Outline(const VehiclePose& pose) const;

  // The frame supplied by rows: rows(first, last) returns the image with at
  // least those rows (clamped to the image) filled in, so a frame kept
  // compressed decodes only what the warp samples.
  using RowSource = std::function<const cv::Mat&(int first, int last)>;
  // neighbours: poses of the previous and/or next painted frames (at most
  // two; see blend_rule.h). nullopt when the frame does not see the seabed.
  std::optional<WarpedFrame> Warp(const RowSource& rows, const VehiclePose& pose,
                                  const std::vector<VehiclePose>& neighbours = {}) const;
  // image: CV_8UC1 / CV_8UC3 matching `channels`, of the camera's size.
  std::optional<WarpedFrame> Warp(const cv::Mat& image, const VehiclePose& pose,
                                  const std::vector<VehiclePose>& neighbours = {}) const;

 private:
  // A block row's kept pixels (bit i: pixel i) and where the row lies in the raw image.
  struct KeptRow {
    int x, y;  // box pixel of the row's first pixel
    uint64_t mask;
    float u0, du, v0, dv;
  };
  // Pass 2; returns the raw rows the kept pixels sample, {first, last} (first > last: none).
  std::array<int, 2> Weigh(const MappingGrid& grid, int neighbours, const float* inv_seam, int box_width,
                           int box_height, PaintCanvas* canvas, std::vector<KeptRow>* kept) const;
  // Pass 3.
  void Sample(const cv::Mat& image, const std::vector<KeptRow>& kept, PaintCanvas* canvas) const;

  SeabedProjection projection_;
  std::unique_ptr<SurfaceProjection> surface_;  // null: flat
  ImageShape shape_;
  FeatherCurve feather_;
  WarpOptions options_;
};

}  // namespace seamap
