#pragma once
// The virtual subsea object of `seamap simulate-stereo`: a wellhead-like
// structure (a frame of beams, a column, a 24-facet cylindrical cover, pipes,
// a valve wheel, instrument boxes, a stencilled plate) on a 20 x 20 m
// seabed, built of planar triangles and shaded by solid procedural textures:
// a texture is a function of the 3D point, so any view samples it exactly,
// with no texture memory and no resampling.
//
// Scene frame (= the truth's object frame): origin on the seabed under the
// object, x east, y north, z up, metres. The layout varies with the seed.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/terrain/height_grid.h"

namespace seamap {

enum class SceneMaterial : uint8_t { kSeabed, kSteel, kCover, kPipe, kValve, kPlate };

struct SceneTriangle {
  Eigen::Vector3d a, b, c;  // scene frame
  SceneMaterial material = SceneMaterial::kSeabed;
};

struct StereoSceneOptions {
  uint64_t seed = 1;
  // Fine texture on the object: 1 fouled, rusty steel; about 0.15 plain paint
  // (the paper's reason for edges); 0 a flat colour per face.
  double object_texture = 1;
  double seabed_size_m = 20;
  bool with_object = true;  // false: bare seabed (tests)
  // Relief of the seabed (core/sim/seabed_relief.h: rms height, wavelengths
  // 0.5-4 m) about z = 0, as a mesh of relief_cell_m squares; 0: a plane.
  double relief_rms_m = 0;
  double relief_cell_m = 0.1;
};

class StereoScene {
 public:
  static StereoScene Wellhead(const StereoSceneOptions& options);
  // A bare textured plane z = 0 (tests): seabed material only; with
  // options.relief_rms_m the relief's mesh instead.
  static StereoScene Plane(const StereoSceneOptions& options);
  // The seabed's true height (z) at scene point (x, y): 0 on a plane.
  double SeabedZ(double x_m, double y_m) const;

  // Reflectance (0-1) of a material at a scene point.
  float Albedo(SceneMaterial material, const Eigen::Vector3d& p) const;

  std::vector<SceneTriangle> triangles;
  std::vector<std::pair<std::string, Eigen::Vector3d>> check_points;  // on the object, scene frame
  double top_z_m = 0;                                                 // the cover's top
  double footprint_m = 0;                                             // the object's width
  std::string layout;                                                 // short description
  // relief_rms_m > 0: heights on the scene's x (east) and y (north), metres up.
  std::shared_ptr<const HeightGrid> relief;

 private:
  uint32_t seed_ = 1;
  double object_texture_ = 1;
};

// Seeded smooth noise in [-1, 1] (value noise, quintic fade): the texture
// building block, exposed for tests.
float ValueNoise3(const Eigen::Vector3d& p, uint32_t seed);

}  // namespace seamap
