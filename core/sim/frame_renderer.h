#pragma once
// Renders what the camera sees of a seabed texture from a pose, by casting
// the ray of every raw (distorted) pixel onto the seabed plane: exact for
// any attitude, distortion and mounting, and independent of the homography
// code the mosaic uses (so tests comparing the two are not circular).
// With a terrain (SetTerrain) the rays are cast onto the rugged seabed
// instead, the texture draped over it (its pixel at the hit's east/north).
#include <cstdint>
#include <memory>

#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/sim/seabed_texture.h"
#include "core/terrain/height_grid.h"
#include "core/terrain/height_grid_ray.h"

namespace seamap {

// Underwater image degradations, each 0 (off) to about 1 (strong).
struct Degradations {
  double vignetting = 0;   // artificial light: bright centre, dark corners
  double color_cast = 0;   // water absorbs red strongly, blue a little (colour only)
  double haze = 0;         // I = J t + A (1 - t), t = exp(-0.4 * haze * range_m), bluish A
  double noise_sigma = 0;  // gaussian noise, standard deviation in 8-bit units
  double blur_px = 0;      // motion blur: a line of this length along the image's rows (the camera moving)

  bool Any() const { return vignetting > 0 || color_cast > 0 || haze > 0 || noise_sigma > 0 || blur_px > 0; }
  // What `--degrade` turns on.
  static Degradations Moderate() { return {0.6, 0.6, 0.4, 2.0}; }
};

class FrameRenderer {
 public:
  FrameRenderer(const CameraModel& camera, const Degradations& degradations);

  // From now on, cast every ray onto this height model (first hit, so
  // relief hides what lies behind it) instead of the plane: the camera sits
  // at height -depth_m (plus its mounting offset), pose.altitude_m is not
  // used, and the haze sees the true range. Without it (the default) the
  // plane path is unchanged, byte for byte.
  void SetTerrain(const HeightGrid& terrain);
  const HeightGridRayCaster* terrain() const { return terrain_.get(); }

  // Axis-aligned local bounds (x = east, y = north) of the footprint, from
  // the rays of every border pixel. False when some border ray misses the seabed.
  bool GroundBounds(const VehiclePose& pose, cv::Rect2d* bounds) const;

  // One frame with the texture's type (channels, depth); pixels whose ray
  // misses the texture are 0. noise_seed makes the noise reproducible.
  cv::Mat Render(const SeabedTexture& texture, const VehiclePose& pose, uint64_t noise_seed) const;

  const CameraModel& camera() const { return camera_; }

 private:
  // Texture coordinates (remap maps) and ranges (with haze) of every pixel,
  // on the plane or on the terrain.
  void PlaneMaps(const SeabedTexture& texture, const VehiclePose& pose, cv::Mat1f* map_x, cv::Mat1f* map_y,
                 cv::Mat1f* range) const;
  void TerrainMaps(const SeabedTexture& texture, const VehiclePose& pose, cv::Mat1f* map_x, cv::Mat1f* map_y,
                   cv::Mat1f* range) const;

  CameraModel camera_;
  Degradations degradations_;
  std::shared_ptr<const HeightGridRayCaster> terrain_;
  cv::Mat2f rays_;      // undistorted normalised (x, y) of each raw pixel; z = 1
  cv::Mat1f ray_norm_;  // |(x, y, 1)|, for the range to the seabed
  // Vignetting (lamp falloff) times the colour cast, per pixel.
  cv::Mat1f gain_gray_;
  cv::Mat3f gain_bgr_;
  cv::Mat1f noise_pool_;  // gaussian samples, sigma = noise_sigma
};

}  // namespace seamap
