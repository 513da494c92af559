#pragma once
// Places one frame on the map. For every output pixel (Web Mercator global
// pixels at the base zoom, inside the frame's bounding box) it finds where the
// pixel comes from in the raw image — inverse seabed homography, then the lens
// distortion model — samples the raw frame there bilinearly (no separate
// undistortion pass) and computes the feather weight: a tent that is 1 at the
// image centre and falls to 0 at the raw image edges.
//
// Consecutive frames of a survey overlap many times over (about 10x along
// track at 5 frames/s). Given the poses of the previous and next painted
// frames, a frame hands every map pixel that a neighbour sees more centrally
// (smaller distance from the image centre) over to that neighbour, with its
// weight ramping to zero across a seam that spans `seam_band` of the way from
// the midpoint to the neighbour's centre, so seams stay feathered. No pixel
// is lost: a pixel goes only to a frame that sees it more centrally, and the
// most central of a run of frames keeps it. Lateral overlaps between survey
// lines are not neighbours and blend in full.
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/geo/lat_lon.h"
#include "core/geo/local_frame.h"

namespace seamap {

struct WarpedFrame {
  // The frame's bounding box at the base zoom (global pixels): what it is over.
  int64_t box_x0 = 0, box_y0 = 0;
  int box_width = 0, box_height = 0;
  // The part it paints (often a band of the box, see below).
  int64_t x0 = 0, y0 = 0;  // global pixel of pixels(0,0) at the base zoom
  cv::Mat pixels;          // CV_8UC1 (gray) or CV_8UC3 (BGR)
  cv::Mat weight;          // CV_8UC1, 0 where the frame paints nothing, 1..255 elsewhere
  // Per row y, runs[run_offset[y] .. run_offset[y + 1]) are column ranges
  // [begin, end), in order, outside which weight is 0 (a band and the
  // slivers along the frame's sides leave most of a span empty). Warp always
  // fills them; a frame made by hand may leave run_offset empty, and then
  // every pixel counts, by its weight.
  std::vector<int> run_offset;
  std::vector<std::array<int, 2>> runs;
};

// Whether the frame paints any pixel of `roi` (in its pixels' coordinates):
// only its runs are looked at.
bool PaintsAny(const WarpedFrame& frame, const cv::Rect& roi);

// A pixel a warp leaves out, unsampled (see FrameWarper::Warp's `tail`):
// where it is on the map, its weight, and where it samples the raw frame.
struct TailPixel {
  int64_t x = 0, y = 0;  // global pixel at the base zoom
  float u = 0, v = 0;    // raw image position
  uint8_t weight = 0;    // 1..255, as in WarpedFrame::weight
};

class FrameWarper {
 public:
  // channels: 1 (gray mosaic) or 3 (colour mosaic). seam_band in (0, 1]
  // (see above); 0: no handover, every overlapping frame blends everywhere.
  FrameWarper(const CameraModel& camera, const LocalFrame& frame, int zoom, int tile_size, int channels,
              double feather_power, double seam_band = 0);

  // The mapping is evaluated exactly every `step` map pixels in x and y and
  // interpolated bilinearly in between: it is smooth (homography and lens
  // polynomial), so at the default step it stays within a few hundredths of
  // a pixel of the exact one (tested against step 1) at a 16th of the cost.
  void SetGridStep(int step) { grid_step_ = step < 1 ? 1 : step > 64 ? 64 : step; }  // 1..64

  // Where the raw image corners land, or nullopt when the frame does not see the seabed.
  std::optional<std::array<LatLon, 4>> Footprint(const VehiclePose& pose) const;
  // The same corners in the local frame (metres east/north).
  std::optional<std::array<LocalXY, 4>> GroundCorners(const VehiclePose& pose) const;
  // Whether the whole image border lands on the seabed (what Warp needs).
  bool SeesSeabed(const VehiclePose& pose) const;
  // Where the frame lands at the base zoom, known before warping: its
  // bounding box in global pixels {x0, y0, width, height} (WarpedFrame's
  // box_*) and where the raw image corners land (global pixel-index
  // coordinates: left-top, right-top, right-bottom, left-bottom). nullopt
  // when the frame does not see the seabed.
  struct MapOutline {
    std::array<int64_t, 4> box;
    std::array<cv::Point2d, 4> corners;
  };
  std::optional<MapOutline> Outline(const VehiclePose& pose) const;

  // image: CV_8UC1 / CV_8UC3 matching `channels`, of the camera's size.
  // neighbours: poses of the previous and/or next painted frames (see above; at most two).
  // Returns nullopt when the frame does not see the seabed.
  std::optional<WarpedFrame> Warp(const cv::Mat& image, const VehiclePose& pose,
                                  const std::vector<VehiclePose>& neighbours = {}) const;
  // The same with the frame supplied by rows: rows(first, last) returns the
  // image with at least those rows (clamped to the image) filled in, so a
  // frame kept compressed decodes only what the warp samples.
  //
  // With `tail`, pixels within kTailEdge raw pixels of the image's left and
  // right edges that sample rows below (lower tail) or above (upper tail)
  // every other painted pixel's are left out and returned there instead,
  // unsampled, so those rows are not decoded. Along a survey line these are
  // slivers of swath edge that the neighbours miss when the footprint drifts
  // sideways: the upper half of one side, the lower half of the other.
  // Rows below the others' are never decoded; rows above are only skipped
  // (Huffman-decoded without the inverse DCT, at about a third of the cost
  // of decoding them). Usually another survey line covers them (see
  // MosaicBuilder).
  using RowSource = std::function<const cv::Mat&(int first, int last)>;
  // `tail_sides` chooses the edges and halves: any of kTailLowerLeft,
  // kTailLowerRight, kTailUpperLeft and kTailUpperRight.
  static constexpr unsigned kTailLowerLeft = 1, kTailLowerRight = 2, kTailUpperLeft = 4, kTailUpperRight = 8;
  static constexpr unsigned kTailAll = 15;
  std::optional<WarpedFrame> Warp(const RowSource& rows, const VehiclePose& pose,
                                  const std::vector<VehiclePose>& neighbours = {},
                                  std::vector<TailPixel>* tail = nullptr, unsigned tail_sides = kTailAll) const;
  static constexpr float kTailEdge = 8.0f;

 private:
  // The first `count` image border samples (corners, centre, edges) on the
  // map, in global pixel-index coordinates; nullopt unless the whole border
  // lands on the seabed.
  std::optional<std::vector<cv::Point2d>> MapBorder(const VehiclePose& pose, size_t count = SIZE_MAX) const;
  bool SeesSeabed(const Eigen::Matrix3d& image_to_ground) const;
  // Box pixel (relative to x0, y0) -> normalised camera coordinates of a frame
  // whose border lies at `global` on the map.
  cv::Matx33d BoxToNormalised(const std::vector<cv::Point2d>& global, int64_t x0, int64_t y0) const;

  CameraModel camera_;
  LocalFrame frame_;
  int zoom_, tile_size_, channels_;
  double feather_power_, seam_band_;
  std::vector<cv::Point2d> border_;  // raw image border samples, undistorted: 4 corners, the
                                     // principal point, then points along the edges
  double max_r2_ = 0;                // beyond this normalised radius² a point is outside the image
  int grid_step_ = 16;
  std::vector<float> weight_lut_;  // tent^power, indexed by tent * (kLut - 1)
};

}  // namespace seamap
