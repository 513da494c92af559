#include "core/stereo/stereo_calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

StereoCalibration Rig(double toe_in_deg = 0.3) {
  StereoCalibration c;
  c.image_size = {1200, 900};
  c.K1 = c.K2 = cv::Matx33d(1040, 0, 599.5, 0, 1040, 449.5, 0, 0, 1);
  const double a = toe_in_deg * M_PI / 180;
  c.R = cv::Matx33d(std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a));
  c.T = cv::Vec3d(-0.25, 0, 0);
  c.Rectify();
  return c;
}

TEST(StereoCalibration, FileRoundTripAndErrorsNamingTheKey) {
  testing::TempDir dir;
  const std::string path = (dir / "stereo.yaml").string();
  SaveStereoCalibration(Rig(), path);
  const StereoCalibration c = LoadStereoCalibration(path);
  EXPECT_EQ(c.image_size, cv::Size(1200, 900));
  EXPECT_NEAR(c.rig.baseline_m, 0.25, 1e-9);
  EXPECT_NEAR(c.rig.f, 1040, 15);  // rectified (alpha 0 zooms in a little)

  const auto expect_error = [&](const std::string& text, const std::string& key) {
    testing::WriteFile(dir / "bad.yaml", text);
    try {
      LoadStereoCalibration((dir / "bad.yaml").string());
      ADD_FAILURE() << "accepted: " << key;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), key) << e.what();
    }
  };
  const std::string k = "!!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ ";
  const std::string good_k = k + "1040., 0., 599.5, 0., 1040., 449.5, 0., 0., 1. ]\n";
  const std::string r =
      "R: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1., 0., 0., 0., 1., 0., 0., 0., 1. ]\n";
  const auto t = [](double x) {
    return "T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ " + std::to_string(x) + ", 0., 0. ]\n";
  };
  const std::string head = "%YAML:1.0\n---\nimage_width: 1200\nimage_height: 900\n";
  expect_error(head + "K1: " + good_k + r + t(-0.25), "K2");
  expect_error(head + "K1: " + k + "0., 0., 599.5, 0., 1040., 449.5, 0., 0., 1. ]\nK2: " + good_k + r + t(-0.25), "K1");
  expect_error(head + "K1: " + good_k + "K2: " + good_k + r + t(-250), "T");
  expect_error("%YAML:1.0\n---\nK1: " + good_k + "K2: " + good_k + r + t(-0.25), "image_width");
}

TEST(StereoCalibration, TriangulationRecoversPointsThroughARotatedRig) {
  const StereoCalibration c = Rig(0.3);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 50; ++k) {
    const Eigen::Vector3d p(u(rng), u(rng) * 0.8, 3.6 + 3 * std::abs(u(rng)));
    const cv::Point2d l = c.RectifyLeft({c.ProjectRaw(p, false)})[0];
    const cv::Point2d r = c.RectifyRight({c.ProjectRaw(p, true)})[0];
    EXPECT_NEAR(l.y, r.y, 1e-6);
    // Dropping R1^T (the rectified frame's rotation) would tilt this by 0.15 deg: ~10 mm at 3.6 m.
    EXPECT_LT((c.rig.Triangulate(l, r) - p).norm(), 1e-6);
  }
}

TEST(StereoCalibration, DepthSpreadMatchesTheCovariance) {
  const StereoCalibration c = Rig(0.3);
  const Eigen::Vector3d p(0.2, -0.1, 3.6);
  const cv::Point2d l0 = c.RectifyLeft({c.ProjectRaw(p, false)})[0];
  const cv::Point2d r0 = c.RectifyRight({c.ProjectRaw(p, true)})[0];
  const double sigma_px = 0.2;
  std::mt19937 rng(9);
  std::normal_distribution<double> n(0, sigma_px);
  double sum_sq = 0;
  const int trials = 4000;
  for (int k = 0; k < trials; ++k) {
    const Eigen::Vector3d q = c.rig.Triangulate(l0 + cv::Point2d(n(rng), n(rng)), r0 + cv::Point2d(n(rng), n(rng)));
    sum_sq += (q - p).squaredNorm();
  }
  const double spread = std::sqrt(sum_sq / trials);
  const double predicted = std::sqrt(c.rig.TriangulationCovariance(l0, r0, sigma_px).trace());
  // Depth dominates: Z^2 sigma_d / (f B) = 3.6^2 * 0.28 / 260 = 14 mm.
  EXPECT_NEAR(spread, predicted, 0.2 * predicted);
  EXPECT_GT(spread, 0.01);
}

}  // namespace
}  // namespace seamap
