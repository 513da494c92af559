#include "core/sim/seabed_relief.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

constexpr double kMaxCells = 4e8;

// 0 below lo, 1 above hi, a raised cosine between.
double Ramp(double x, double lo, double hi) {
  if (x <= lo) return 0;
  if (x >= hi) return 1;
  return 0.5 - 0.5 * std::cos(M_PI * (x - lo) / (hi - lo));
}

// Zero mean, rms `rms_m` over the finite cells.
void ScaleToRms(cv::Mat1f* heights, double rms_m, const std::string& file) {
  cv::Scalar mean, stddev;
  cv::meanStdDev(*heights, mean, stddev);
  if (!(stddev[0] > 1e-12)) throw InputError(file, 0, "--relief-texture", "the image of heights is flat (one value)");
  heights->convertTo(*heights, CV_32F, rms_m / stddev[0], -mean[0] * rms_m / stddev[0]);
}

// Band-limited 1/f^2 gaussian field on a grid of `cell_m` cells.
cv::Mat1f SpectralField(cv::Size size, double cell_m, double min_wavelength_m, double max_wavelength_m, uint64_t seed) {
  const cv::Size padded(cv::getOptimalDFTSize(size.width), cv::getOptimalDFTSize(size.height));
  cv::Mat1f noise(padded);
  cv::RNG rng(seed ^ 0x72656c696566ull);  // "relief"
  rng.fill(noise, cv::RNG::NORMAL, 0, 1);
  cv::Mat spectrum;
  cv::dft(noise, spectrum, cv::DFT_COMPLEX_OUTPUT);
  const double f_lo = 1 / max_wavelength_m, f_hi = 1 / min_wavelength_m;  // cycles per metre
  const double taper = 0.25;                                              // of an octave-ish, in log2 frequency
  for (int r = 0; r < padded.height; ++r) {
    const int kr = r <= padded.height / 2 ? r : r - padded.height;
    const double fy = kr / (padded.height * cell_m);
    cv::Vec2f* row = spectrum.ptr<cv::Vec2f>(r);
    for (int c = 0; c < padded.width; ++c) {
      const int kc = c <= padded.width / 2 ? c : c - padded.width;
      const double fx = kc / (padded.width * cell_m);
      const double f = std::hypot(fx, fy);
      double gain = 0;
      if (f > 0) {
        const double l = std::log2(f);
        gain = Ramp(l, std::log2(f_lo) - taper, std::log2(f_lo) + taper) *
               (1 - Ramp(l, std::log2(f_hi) - taper, std::log2(f_hi) + taper)) / (f * f);
      }
      row[c] *= static_cast<float>(gain);
    }
  }
  cv::Mat1f field;
  cv::dft(spectrum, field, cv::DFT_INVERSE | cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
  return field(cv::Rect(0, 0, size.width, size.height)).clone();
}

cv::Mat1f LoadHeightImage(const std::string& file) {
  const cv::Mat image = cv::imread(file, cv::IMREAD_UNCHANGED);
  if (image.empty())
    throw InputError(file, 0, "--relief-texture",
                     "cannot read the image of heights (expected an 8/16-bit gray PNG or a float TIFF)");
  if (image.channels() != 1)
    throw InputError(
        file, 0, "--relief-texture",
        "expected a single-channel (gray) image of heights, found " + std::to_string(image.channels()) + " channels");
  cv::Mat1f heights;
  image.convertTo(heights, CV_32F);
  if (!cv::checkRange(heights, true, nullptr, -1e30, 1e30))
    throw InputError(file, 0, "--relief-texture", "holds non-finite heights (NaN or infinity)");
  return heights;
}

}  // namespace

void SeabedReliefOptions::Check() const {
  if (!(rms_m >= 0 && rms_m <= 10)) throw InputError("", 0, "--relief", "expected an rms height of 0-10 metres");
  if (!texture_file.empty() && rms_m == 0)
    throw InputError(texture_file, 0, "--relief-texture", "needs --relief M > 0: the rms height to scale it to");
  if (!(cell_m > 0)) throw InputError("", 0, "--relief", "the relief's cell size must be positive");
  if (!(min_wavelength_m > 2 * cell_m && max_wavelength_m > min_wavelength_m))
    throw InputError("", 0, "--relief", "the relief's wavelengths must exceed two cells, max above min");
}

HeightGrid MakeSeabedRelief(const SeabedReliefOptions& o, const cv::Rect2d& extent, double mean_height_m,
                            uint64_t seed) {
  o.Check();
  HeightGrid grid;
  grid.cell_m = o.cell_m;
  const int cols = std::max(2, static_cast<int>(std::ceil(extent.width / o.cell_m)));
  const int rows = std::max(2, static_cast<int>(std::ceil(extent.height / o.cell_m)));
  if (static_cast<double>(rows) * cols > kMaxCells)
    throw InputError("", 0, "--relief", "the survey area is too large for the relief grid; use a shorter survey");
  grid.east0_m = extent.x + o.cell_m / 2;
  grid.north0_m = extent.y + extent.height - o.cell_m / 2;
  grid.has_depth_datum = true;

  cv::Mat1f relief(rows, cols, 0.f);
  if (!o.Flat() && !o.texture_file.empty()) {
    const cv::Mat1f source = LoadHeightImage(o.texture_file);
    const bool shrink = source.cols > cols || source.rows > rows;
    cv::resize(source, relief, relief.size(), 0, 0, shrink ? cv::INTER_AREA : cv::INTER_LINEAR);
    ScaleToRms(&relief, o.rms_m, o.texture_file);
  } else if (!o.Flat()) {
    // Coarse synthesis, padded by the longest wavelength so that the DFT's
    // wrap-around stays outside the extent.
    const double coarse_m = o.min_wavelength_m / 8;
    const double pad_m = o.max_wavelength_m;
    const cv::Size coarse(static_cast<int>(std::ceil((extent.width + 2 * pad_m) / coarse_m)) + 4,
                          static_cast<int>(std::ceil((extent.height + 2 * pad_m) / coarse_m)) + 4);
    const cv::Mat1f field = SpectralField(coarse, coarse_m, o.min_wavelength_m, o.max_wavelength_m, seed);
    // Coarse cell (0, 0) is centred at (east0 - pad, north0 + pad).
    cv::Mat1f map_x(rows, cols), map_y(rows, cols);
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        map_x(r, c) = static_cast<float>((c * o.cell_m + pad_m) / coarse_m);
        map_y(r, c) = static_cast<float>((r * o.cell_m + pad_m) / coarse_m);
      }
    cv::remap(field, relief, map_x, map_y, cv::INTER_CUBIC, cv::BORDER_REFLECT);
    ScaleToRms(&relief, o.rms_m, "");
  }
  grid.height_m = relief + static_cast<float>(mean_height_m);
  grid.sigma_m = cv::Mat1f(rows, cols, 0.f);
  return grid;
}

}  // namespace seamap
