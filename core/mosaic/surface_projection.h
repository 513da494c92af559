#pragma once
// A true orthophoto's projection: the seabed as a height model (HeightGrid)
// instead of the plane at each frame's altitude. A map pixel is a point
// (east, north) whose height the model gives; that 3-D point goes into the
// camera (pinhole, then the lens model), and a frame that does not see it
// (the line from the camera to it passes below the surface) does not paint
// it, so another frame that sees it does. Where the model has a hole, or
// ends, the frame's own plane stands in for it (today's flat projection).
//
// Heights are metres up on the model's datum; a camera is at height
// -depth_m (plus its mounting offset), as in core/terrain/height_grid.h.
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "core/camera/vehicle_pose.h"
#include "core/mosaic/box_mapping.h"
#include "core/mosaic/seabed_projection.h"
#include "core/terrain/height_grid.h"
#include "core/terrain/height_grid_ray.h"
#include "core/terrain/line_of_sight.h"

namespace seamap {

// Where one frame's camera is, in local metres (east, north, up), and how it is turned.
struct CameraPlacement {
  Eigen::Vector3d eye_enu;
  Eigen::Matrix3d camera_from_enu;
  double plane_up_m;  // the frame's flat seabed (altitude_m below the vehicle): the stand-in for holes
};
CameraPlacement PlaceCamera(const CameraModel& camera, const VehiclePose& pose);

// One frame's mapping over a box on the map, through the surface.
class SurfaceMapping : public BoxMapping {
 public:
  // box_to_map: local metres <-> global pixels around the box; (x0, y0): its top-left global pixel.
  SurfaceMapping(const SeabedProjection& flat, const LineOfSight& surface, const VehiclePose& pose,
                 const SeabedProjection::MapTangent& box_to_map, int64_t x0, int64_t y0);
  RawPosition ToRaw(double x, double y) const override;
  // The seabed point seen at box pixel (x, y); false: the model has no height there (the plane stands in).
  bool PointAt(double x, double y, Eigen::Vector3d* east_north_up) const;
  // The raw image position of a seabed point, invalid when the camera does not see it.
  RawPosition See(const Eigen::Vector3d& east_north_up) const;

 private:
  const SeabedProjection& flat_;
  const LineOfSight& surface_;
  CameraPlacement camera_;
  SeabedProjection::MapTangent box_to_map_;
  int64_t x0_, y0_;
};

class SurfaceProjection {
 public:
  SurfaceProjection(const SeabedProjection& flat, std::shared_ptr<const HeightGrid> surface);

  // The frame on the map with its border's rays meeting the surface (as
  // SeabedProjection::Outline, a few pixels larger for the relief between
  // border samples). nullopt unless the whole border sees the seabed.
  std::optional<SeabedProjection::MapOutline> Outline(const VehiclePose& pose) const;

  // The mappings of a frame and its neighbours over the frame's box on the
  // map (the first for `views[0]`, which `frame` is the outline of).
  std::vector<std::unique_ptr<BoxMapping>> Mappings(const SeabedProjection::MapOutline& frame,
                                                    const std::vector<VehiclePose>& views) const;

  const HeightGrid& surface() const { return sight_.grid(); }

 private:
  const SeabedProjection& flat_;
  HeightGridRayCaster rays_;  // the border's rays onto the surface
  LineOfSight sight_;         // heights and occlusion
};

}  // namespace seamap
