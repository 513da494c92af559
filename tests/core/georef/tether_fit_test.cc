#include "core/georef/tether_fit.h"

#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>

namespace seamap {
namespace {

// Four 100 m legs 15 m apart, flown alternately north and south, at 12 m depth;
// the buoy 27 m behind on each. Truth: world = s R slam + t.
struct Case {
  Similarity truth;
  std::vector<Eigen::Vector3d> slam, offsets, buoy;
  std::vector<double> weights;
};

Case MakeCase(double gps_sigma_m, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, 1);
  Case c;
  c.truth.scale = 3.7;
  c.truth.rotation = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  c.truth.translation = {40, -25, 3};
  for (int leg = 0; leg < 4; ++leg)
    for (int k = 0; k <= 100; k += 2) {
      const double north = leg % 2 ? 100 - k : k;
      const Eigen::Vector3d world(15.0 * leg, north, -12);
      const Eigen::Vector3d offset(0, leg % 2 ? -27.0 : 27.0, 0);
      c.slam.push_back(c.truth.rotation.transpose() * (world - c.truth.translation) / c.truth.scale);
      c.offsets.push_back(offset);
      c.buoy.push_back(world - offset + gps_sigma_m * Eigen::Vector3d(noise(rng), noise(rng), 0));
      c.weights.push_back(1.0);
    }
  return c;
}

double Cost(const Case& c, const Similarity& fit, const Eigen::Matrix3d& offsets_rotation) {
  double sum = 0;
  for (size_t i = 0; i < c.slam.size(); ++i) {
    const Eigen::Vector3d o = offsets_rotation.transpose() * c.offsets[i];
    sum += (fit.rotation * (fit.scale * c.slam[i] - o) + fit.translation - c.buoy[i]).squaredNorm();
  }
  return sum;
}

TEST(FitThroughTether, RecoversTheTruthFromAWrongScaleAndTranslation) {
  const Case c = MakeCase(0, 1);
  Similarity start = c.truth;
  start.scale *= 1.05;
  start.translation += Eigen::Vector3d(3, -2, 1);
  const Similarity fit = FitThroughTether(start, c.slam, c.offsets, c.buoy, c.weights);
  EXPECT_NEAR(fit.scale, c.truth.scale, 1e-9);
  EXPECT_LT((fit.rotation - c.truth.rotation).norm(), 1e-9);
  EXPECT_LT((fit.translation - c.truth.translation).norm(), 1e-7);
}

TEST(FitThroughTether, MinimisesTheBuoyResidualsItIsGiven) {
  const Case c = MakeCase(1.5, 2);
  Similarity start = c.truth;
  start.scale *= 0.99;
  const Similarity fit = FitThroughTether(start, c.slam, c.offsets, c.buoy, c.weights);
  EXPECT_GT(fit.rotation.determinant(), 0.999);
  const double best = Cost(c, fit, start.rotation);
  EXPECT_LT(best, Cost(c, start, start.rotation));
  // A small step of any parameter away from it costs more.
  for (int axis = 0; axis < 3; ++axis) {
    Similarity moved = fit;
    moved.rotation = Eigen::AngleAxisd(1e-4, Eigen::Vector3d::Unit(axis)).toRotationMatrix() * fit.rotation;
    EXPECT_GT(Cost(c, moved, start.rotation), best) << axis;
  }
  Similarity scaled = fit;
  scaled.scale *= 1.0001;
  EXPECT_GT(Cost(c, scaled, start.rotation), best);
}

}  // namespace
}  // namespace seamap
