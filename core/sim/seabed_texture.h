#pragma once
// The simulated seabed: an image georeferenced in the mission's local frame.
// Texture pixel (i, j) has its centre at
//   east  = east_min  + (i + 0.5) * res_m,
//   north = north_max - (j + 0.5) * res_m.
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

#include "core/geo/lat_lon.h"
#include "core/geo/local_frame.h"

namespace seamap {

struct SeabedTexture {
  cv::Mat image;  // CV_8UC1/CV_8UC3/CV_16UC1/CV_16UC3 (BGR)
  double res_m = 0;
  double east_min = 0;
  double north_max = 0;

  // Texture pixel coordinates (centre convention, as cv::remap uses them).
  double Column(double east) const { return (east - east_min) / res_m - 0.5; }
  double Row(double north) const { return (north_max - north) / res_m - 0.5; }
};

// A procedural seabed covering `size` pixels of `res_m` metres: multi-octave
// noise from a few pixels to metres, sand ripples in patches, and scattered
// shaded rocks and shells, so that it has strong features at every scale.
// Gray, or brownish/greenish sand tones when `color`. bit_depth 8 or 16.
// Same seed, same texture.
cv::Mat MakeProceduralTexture(cv::Size size, double res_m, bool color, int bit_depth, uint64_t seed);

// Reads any image OpenCV can decode and converts it to the requested channels
// and depth. Throws InputError naming the file.
cv::Mat LoadTextureImage(const std::string& path, bool color, int bit_depth);

// Writes truth_dir/texture.png and truth_dir/texture.json
// {"origin":[lat,lon],"res_m","east_min","north_max","width","height"}.
void SaveTruth(const SeabedTexture& texture, LatLon origin, const std::string& truth_dir);

}  // namespace seamap
