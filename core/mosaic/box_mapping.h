#pragma once
// The seam between the warp and the seabed's shape: how a pixel of a frame's
// box on the map (box pixel-index coordinates) maps to one frame's raw image.
// The warp evaluates it on its grid (mapping_grid.h) for the frame and its
// neighbours, and knows nothing else of the geometry.
//   PlaneMapping    the seabed as a plane at the frame's altitude (a homography, then the lens);
//   SurfaceMapping  the seabed as a height model, with occlusion (surface_projection.h).
#include <opencv2/core.hpp>

#include "core/mosaic/seabed_projection.h"

namespace seamap {

class BoxMapping {
 public:
  virtual ~BoxMapping() = default;
  // Where this frame's raw image sees box pixel (x, y); invalid where it
  // cannot (behind the camera, far outside the image, hidden by the seabed).
  virtual RawPosition ToRaw(double x, double y) const = 0;
};

// The flat seabed's mapping: SeabedProjection::CameraFromBox, then the lens.
class PlaneMapping : public BoxMapping {
 public:
  PlaneMapping(const SeabedProjection& projection, const cv::Matx33d& camera_from_box)
      : projection_(projection), camera_from_box_(camera_from_box) {}
  RawPosition ToRaw(double x, double y) const override { return projection_.ToRaw(camera_from_box_, x, y); }

 private:
  const SeabedProjection& projection_;
  cv::Matx33d camera_from_box_;
};

}  // namespace seamap
