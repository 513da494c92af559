#pragma once
// Where a frame lands on the map: the camera's rays through the raw image
// (lens distortion undone) meet the seabed plane `altitude_m` below the
// vehicle (core/camera/frame_projector), and the seabed's local metres go to
// Web Mercator global pixels at the base zoom. And back: from a map pixel to
// the raw image position that sees it (homography, then the lens model).
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/geo/lat_lon.h"
#include "core/geo/local_frame.h"

namespace seamap {

// A raw image position, and whether the mapping can be trusted there (in
// front of the camera, not far outside the image).
struct RawPosition {
  float u = 0, v = 0;
  bool valid = false;
  // tan^2 of the angle between the ray to the seabed point and the vertical
  // (SurfaceMapping's: seams on relief go to the most nadir view; 0 elsewhere).
  float slant = 0;
};

class SeabedProjection {
 public:
  SeabedProjection(const CameraModel& camera, const LocalFrame& frame, int zoom, int tile_size);

  // Where the raw image corners land (top-left, top-right, bottom-right,
  // bottom-left), or nullopt when the camera does not see the seabed.
  std::optional<std::array<LocalXY, 4>> GroundCorners(const VehiclePose& pose) const;
  std::optional<std::array<LatLon, 4>> Footprint(const VehiclePose& pose) const;
  // Whether the whole image border lands on the seabed (what warping needs).
  bool SeesSeabed(const VehiclePose& pose) const;

  // The frame on the map at the base zoom: the whole-pixel bounding box
  // {x0, y0, width, height} of its border in global pixels, and where the raw
  // image corners and centre land (global pixel-index coordinates: a pixel's
  // centre is its index). Columns are unwrapped around the mission's origin:
  // near the antimeridian they may run past the world's edge (below 0 or
  // beyond its width), continuous across it. nullopt unless the whole border lands on the seabed.
  struct MapOutline {
    std::array<int64_t, 4> box;
    std::array<cv::Point2d, 4> corners;
    cv::Point2d centre;
  };
  std::optional<MapOutline> Outline(const VehiclePose& pose) const;

  // The mapping from pixels of a box whose top-left global pixel is (x0, y0)
  // to normalised camera coordinates, for a frame whose outline is `frame`.
  cv::Matx33d CameraFromBox(const MapOutline& frame, int64_t x0, int64_t y0) const;
  // The raw image position seen at box pixel (x, y) through such a mapping.
  RawPosition ToRaw(const cv::Matx33d& camera_from_box, double x, double y) const;
  // The raw image position of normalised camera coordinates (x/z, y/z): the
  // lens model, invalid far outside the image.
  RawPosition FromNormalised(double xn, double yn) const;

  // Local metres to global pixels around a seabed point: global pixel-index
  // coordinates = at + east_px * (east - centre.east) + north_px * (north -
  // centre.north), affine to well under a thousandth of a pixel over a frame
  // (PROJ at the point and a metre east and north of it). Columns unwrapped
  // around the mission's origin, as Outline's.
  struct MapTangent {
    LocalXY centre;
    cv::Point2d at, east_px, north_px;
    cv::Point2d ToMap(LocalXY p) const {
      const double de = p.east - centre.east, dn = p.north - centre.north;
      return at + east_px * de + north_px * dn;
    }
    LocalXY ToLocal(cv::Point2d map) const;  // the inverse
  };
  MapTangent TangentAt(LocalXY centre) const;

  const CameraModel& camera() const { return camera_; }
  int tile_size() const { return tile_size_; }
  // The raw image border samples, undistorted (ideal pixels): the four
  // corners, the principal point, then points along the edges.
  const std::vector<cv::Point2d>& border() const { return border_; }

 private:
  // The first `count` image border samples (corners, centre, edges) on the
  // map, in global pixel-index coordinates; nullopt unless the whole border
  // lands on the seabed.
  std::optional<std::vector<cv::Point2d>> MapBorder(const VehiclePose& pose, size_t count = SIZE_MAX) const;
  bool SeesSeabed(const Eigen::Matrix3d& ground_from_image) const;

  CameraModel camera_;
  LocalFrame frame_;
  int zoom_, tile_size_;
  double world_px_ = 0;              // the world's width in global pixels at the zoom
  double origin_x_ = 0;              // the mission origin's global pixel column
  std::vector<cv::Point2d> border_;  // raw image border samples, undistorted: 4 corners, the
                                     // principal point, then points along the edges
  double max_r2_ = 0;                // beyond this normalised radius² a point is outside the image
};

}  // namespace seamap
