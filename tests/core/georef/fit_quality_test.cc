#include "core/georef/fit_quality.h"

#include <gtest/gtest.h>

#include <cmath>

namespace seamap {
namespace {

TEST(EigenRatio, LineAndPlane) {
  std::vector<Eigen::Vector3d> line, plane;
  for (int i = 0; i < 50; ++i) {
    line.push_back({i * 1.0, i * 0.5, 1e-4 * (i % 3)});
    plane.push_back({i % 10 * 1.0, i / 10 * 2.0, 0});
  }
  EXPECT_LT(EigenRatio(line, std::vector<double>(50, 1)), 0.01);
  EXPECT_GT(EigenRatio(plane, std::vector<double>(50, 1)), 0.3);
}

TEST(PredictUncertainty, AveragesToTwoSigmaOverRootN) {
  // N fixes of sigma 1.5 m spread over a level survey, depth far better known:
  // the mapped points' horizontal error averages 2 sigma / sqrt(N) (4
  // parameters seen through 2N observations).
  std::vector<Eigen::Vector3d> slam;
  for (int i = 0; i < 400; ++i) slam.push_back({std::cos(i * 0.7) * (20 + i % 7), std::sin(i * 0.7) * (30 + i % 5), 0});
  Similarity fit;
  fit.scale = 2;
  const double sigma = 1.5;
  const std::vector<double> horizontal(slam.size(), 1 / (sigma * sigma)), vertical(slam.size(), 1e4);
  const FitUncertainty u = PredictUncertainty(fit, slam, horizontal, vertical);
  ASSERT_TRUE(u.ok);
  double sq = 0;
  for (const auto& p : slam) sq += std::pow(u.HorizontalSigma(fit, p), 2);
  EXPECT_NEAR(std::sqrt(sq / slam.size()), 2 * sigma / std::sqrt(400.0), 1e-3);
  EXPECT_NEAR(u.position_sigma_m.x(), sigma / std::sqrt(400.0), 1e-6);
}

}  // namespace
}  // namespace seamap
