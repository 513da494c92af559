#pragma once
// Renders a StereoScene from a calibrated stereo rig with exact geometry:
// every pixel is split into s x s sub-samples placed symmetrically about the
// integer pixel centre (OpenCV's convention), each sub-sample's ray is
// intersected with the nearest triangle (z-buffer), and the solid texture is
// evaluated at that 3D point. Lamps on the rig (1/r^2, Lambert), water
// (I = J e^(-beta r) + A (1 - e^(-beta r))) and sensor noise follow.
// Distortion is not rendered: the rig's D1, D2 must be zero.
#include <cstdint>

#include <opencv2/core.hpp>

#include "core/sim/stereo_scene.h"
#include "core/stereo/rigid_transform.h"
#include "core/stereo/stereo_calibration.h"

namespace seamap {

struct StereoRenderOptions {
  int supersample = 2;       // s: s x s sub-samples per pixel
  double beta_per_m = 0.12;  // water attenuation
  double veil = 0.18;        // A, the water's own brightness (0-1)
  double lamp = 14;          // lamp power: irradiance = lamp / r^2 (+ ambient)
  double ambient = 0.12;     // daylight / other lamps, independent of range
  double noise_sigma = 1.5;  // sensor noise, 8-bit units
  double blur_sigma_px = 0;  // optional optical blur
  void Check() const;        // InputError naming the option
};

struct StereoImages {
  cv::Mat left, right;  // CV_8U gray
};

// object_from_left: the left camera's pose in the scene frame.
StereoImages RenderStereoPair(const StereoScene& scene, const StereoCalibration& calibration,
                              const Rigid& object_from_left, const StereoRenderOptions& options, uint64_t noise_seed);

// One camera (K, no distortion) at object_from_camera: the image before
// noise, as float 0-255 (tests).
cv::Mat1f RenderView(const StereoScene& scene, const cv::Matx33d& K, cv::Size size, const Rigid& object_from_camera,
                     const StereoRenderOptions& options);

}  // namespace seamap
