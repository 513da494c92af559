#pragma once
// Renders what the camera sees of a seabed texture from a pose, by casting
// the ray of every raw (distorted) pixel onto the seabed plane: exact for
// any attitude, distortion and mounting, and independent of the homography
// code the mosaic uses (so tests comparing the two are not circular).
#include <cstdint>

#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/sim/seabed_texture.h"

namespace seamap {

// Underwater image degradations, each 0 (off) to about 1 (strong).
struct Degradations {
  double vignetting = 0;   // artificial light: bright centre, dark corners
  double color_cast = 0;   // water absorbs red strongly, blue a little (colour only)
  double haze = 0;         // I = J t + A (1 - t), t = exp(-0.4 * haze * range_m), bluish A
  double noise_sigma = 0;  // gaussian noise, standard deviation in 8-bit units

  bool Any() const { return vignetting > 0 || color_cast > 0 || haze > 0 || noise_sigma > 0; }
  // What `--degrade` turns on.
  static Degradations Moderate() { return {0.6, 0.6, 0.4, 2.0}; }
};

class FrameRenderer {
 public:
  FrameRenderer(const CameraModel& camera, const Degradations& degradations);

  // Axis-aligned local bounds (x = east, y = north) of the footprint, from
  // the rays of every border pixel. False when some border ray misses the seabed.
  bool GroundBounds(const VehiclePose& pose, cv::Rect2d* bounds) const;

  // One frame with the texture's type (channels, depth); pixels whose ray
  // misses the texture are 0. noise_seed makes the noise reproducible.
  cv::Mat Render(const SeabedTexture& texture, const VehiclePose& pose, uint64_t noise_seed) const;

  const CameraModel& camera() const { return camera_; }

 private:
  CameraModel camera_;
  Degradations degradations_;
  cv::Mat2f rays_;      // undistorted normalised (x, y) of each raw pixel; z = 1
  cv::Mat1f ray_norm_;  // |(x, y, 1)|, for the range to the seabed
  // Vignetting (lamp falloff) times the colour cast, per pixel.
  cv::Mat1f gain_gray_;
  cv::Mat3f gain_bgr_;
  cv::Mat1f noise_pool_;  // gaussian samples, sigma = noise_sigma
};

}  // namespace seamap
