#pragma once
// The ground truth of a simulated survey (truth/texture.png + texture.json,
// and truth/terrain.tif over relief), for accuracy tests: sample the
// seabed's texture and height anywhere in the mission's local frame.
#include <string>

#include <opencv2/core.hpp>

#include "core/geo/lat_lon.h"
#include "core/geo/local_frame.h"
#include "core/sim/seabed_texture.h"
#include "core/terrain/height_grid.h"

namespace seamap {

class GroundTruth {
 public:
  // Reads survey_dir/truth/texture.{png,json}, and truth/terrain.tif when
  // present. Throws InputError naming the file and field.
  static GroundTruth Load(const std::string& survey_dir);

  cv::Mat image;  // as written: 8 or 16 bit, gray or BGR
  double res_m = 0;
  double east_min = 0;
  double north_max = 0;
  LatLon origin;
  // The true seabed heights (metres up from the sea surface, local frame);
  // empty for a flat survey (the seabed is then at -sea_depth).
  HeightGrid terrain;

  SeabedTexture Texture() const { return {image, res_m, east_min, north_max}; }
  // Bilinear value at a local point, in the image's units (0-255 or 0-65535);
  // gray images fill all three channels. False outside the texture.
  bool Sample(LocalXY p, cv::Vec3f* value) const;
  // The true seabed height (metres up) at a local point, bilinear. False
  // outside the terrain or when the survey has none (flat).
  bool SeabedHeight(LocalXY p, double* up_m) const { return terrain.Sample(p, up_m); }
};

// Samples the truth at a grid of local points: east_map and north_map are
// same-size CV_32F or CV_64F matrices of local metres. Returns an image of
// the map's size and the texture's type (bilinear; 0 outside the texture).
cv::Mat RenderTruth(const GroundTruth& truth, const cv::Mat& east_map, const cv::Mat& north_map);

}  // namespace seamap
