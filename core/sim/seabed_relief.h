#pragma once
// The simulated seabed's relief (`seamap simulate --relief M`): a smooth
// random height field, or a gray image of heights, as a HeightGrid in the
// mission's local frame (core/terrain/height_grid.h), heights metres up.
//
// Random relief: spectral synthesis. Gaussian white noise, filtered in the
// Fourier domain to wavelengths between min_wavelength_m and
// max_wavelength_m with an amplitude falling as 1/f^2 (a Brownian surface:
// long swells carry the height, every octave adds as much slope), then scaled to exactly rms_m about its mean.
// The field is synthesised on a coarse grid (8 samples per shortest
// wavelength) and interpolated bicubically onto cell_m cells.
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

#include "core/terrain/height_grid.h"

namespace seamap {

struct SeabedReliefOptions {
  double rms_m = 0;          // --relief: rms height about the mean seabed; 0 = flat
  std::string texture_file;  // --relief-texture: 8/16-bit gray PNG or float TIFF of heights
  double cell_m = 0.02;
  double min_wavelength_m = 0.5;
  double max_wavelength_m = 4;

  bool Flat() const { return rms_m == 0; }
  // Throws InputError naming --relief / --relief-texture.
  void Check() const;
};

// Heights mean_height_m + relief over `extent_m` (x east, y north, local
// metres): cells of cell_m whose centres start half a cell inside the
// extent's north-west corner. A relief texture is stretched over the whole
// extent. sigma_m is 0 (the truth). Same options and seed, same relief.
// Throws InputError naming the texture file when it cannot be read, is not
// a single-channel image, holds non-finite values or is flat.
HeightGrid MakeSeabedRelief(const SeabedReliefOptions& options, const cv::Rect2d& extent_m, double mean_height_m,
                            uint64_t seed);

}  // namespace seamap
