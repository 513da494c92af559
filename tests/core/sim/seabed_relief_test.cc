#include "core/sim/seabed_relief.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

SeabedReliefOptions Rms(double rms_m) {
  SeabedReliefOptions o;
  o.rms_m = rms_m;
  return o;
}

double Rms(const cv::Mat1f& m, double about) {
  return std::sqrt(cv::norm(m - about, cv::NORM_L2SQR) / static_cast<double>(m.total()));
}

InputError ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no InputError";
  return InputError("", 0, "", "");
}

TEST(SeabedRelief, HasTheRequestedRmsAboutTheMeanSeabedAndFollowsTheSeed) {
  const cv::Rect2d extent(-3, -2, 6, 9);
  const HeightGrid g = MakeSeabedRelief(Rms(0.3), extent, -35, 7);
  EXPECT_EQ(g.cols(), 300);
  EXPECT_EQ(g.rows(), 450);
  EXPECT_NEAR(g.east0_m, -2.99, 1e-12);
  EXPECT_NEAR(g.north0_m, 6.99, 1e-12);
  EXPECT_NEAR(cv::mean(g.height_m)[0], -35, 1e-4);
  EXPECT_NEAR(Rms(g.height_m, -35), 0.3, 1e-4);
  EXPECT_EQ(cv::norm(g.sigma_m, cv::NORM_INF), 0);
  const HeightGrid same = MakeSeabedRelief(Rms(0.3), extent, -35, 7);
  EXPECT_EQ(cv::norm(g.height_m, same.height_m, cv::NORM_INF), 0);
  const HeightGrid other = MakeSeabedRelief(Rms(0.3), extent, -35, 8);
  EXPECT_GT(cv::norm(g.height_m, other.height_m, cv::NORM_INF), 0.1);
  // Flat is flat.
  const HeightGrid flat = MakeSeabedRelief(Rms(0), extent, -35, 7);
  EXPECT_EQ(cv::norm(flat.height_m - -35.f, cv::NORM_INF), 0);
}

TEST(SeabedRelief, ItsWavelengthsLieBetweenHalfAMetreAndFourMetres) {
  const HeightGrid g = MakeSeabedRelief(Rms(0.2), {0, 0, 16, 16}, 0, 3);
  // Power spectrum of the (Hann-windowed) field against wavelength.
  cv::Mat1f windowed;
  cv::Mat1f hann;
  cv::createHanningWindow(hann, g.height_m.size(), CV_32F);
  cv::multiply(g.height_m, hann, windowed);
  cv::Mat spectrum;
  cv::dft(windowed, spectrum, cv::DFT_COMPLEX_OUTPUT);
  double in_band = 0, short_waves = 0, total = 0;
  const int rows = spectrum.rows, cols = spectrum.cols;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const int kr = r <= rows / 2 ? r : r - rows, kc = c <= cols / 2 ? c : c - cols;
      const double f = std::hypot(kr / (rows * g.cell_m), kc / (cols * g.cell_m));  // cycles per metre
      if (f == 0) continue;
      const cv::Vec2f z = spectrum.at<cv::Vec2f>(r, c);
      const double power = z[0] * z[0] + z[1] * z[1];
      total += power;
      if (1 / f >= 0.4 && 1 / f <= 5) in_band += power;
      if (1 / f < 0.35) short_waves += power;
    }
  EXPECT_GT(in_band / total, 0.95);
  EXPECT_LT(short_waves / total, 0.005);
}

TEST(SeabedRelief, AnImageOfHeightsIsStretchedAndScaled) {
  testing::TempDir dir;
  // A 16-bit ramp rising to the east.
  cv::Mat1w ramp(10, 50);
  for (int c = 0; c < 50; ++c) ramp.col(c).setTo(1000 + 100 * c);
  const std::string png = (dir / "ramp.png").string();
  ASSERT_TRUE(cv::imwrite(png, ramp));
  SeabedReliefOptions o = Rms(0.25);
  o.texture_file = png;
  const HeightGrid g = MakeSeabedRelief(o, {0, 0, 4, 3}, -20, 1);
  EXPECT_NEAR(Rms(g.height_m, -20), 0.25, 1e-4);
  EXPECT_LT(g.height_m(75, 10), g.height_m(75, 100));
  EXPECT_LT(g.height_m(75, 100), g.height_m(75, 190));
  EXPECT_NEAR(g.height_m(0, 100), g.height_m(149, 100), 1e-6);  // stretched, not tiled
}

TEST(SeabedRelief, BadTexturesAndOptionsAreNamed) {
  testing::TempDir dir;
  const cv::Rect2d extent(0, 0, 2, 2);
  SeabedReliefOptions o = Rms(0.2);
  o.texture_file = (dir / "nothing.png").string();
  InputError e = ErrorOf([&] { MakeSeabedRelief(o, extent, 0, 1); });
  EXPECT_EQ(e.file(), o.texture_file);
  EXPECT_EQ(e.field(), "--relief-texture");

  o.texture_file = (dir / "colour.png").string();
  cv::imwrite(o.texture_file, cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3)));
  e = ErrorOf([&] { MakeSeabedRelief(o, extent, 0, 1); });
  EXPECT_EQ(e.file(), o.texture_file);
  EXPECT_NE(std::string(e.what()).find("single-channel"), std::string::npos);

  o.texture_file = (dir / "flat.png").string();
  cv::imwrite(o.texture_file, cv::Mat(8, 8, CV_8UC1, cv::Scalar(9)));
  e = ErrorOf([&] { MakeSeabedRelief(o, extent, 0, 1); });
  EXPECT_EQ(e.file(), o.texture_file);
  EXPECT_NE(std::string(e.what()).find("flat"), std::string::npos);

  o.rms_m = 0;  // a texture needs an rms to scale to
  EXPECT_EQ(ErrorOf([&] { o.Check(); }).field(), "--relief-texture");
  EXPECT_EQ(ErrorOf([&] { Rms(-1).Check(); }).field(), "--relief");
}

}  // namespace
}  // namespace seamap
