// Stereo pairs as seabed points over relief (issue 29 part 2): the simulator's
// stereo seabed with relief, rendered, matched, triangulated and placed on
// the vehicle's pose, against the scene's true heights; and the height model
// fitted to those points alone.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/sim/stereo_renderer.h"
#include "core/sim/stereo_scene.h"
#include "core/sim/stereo_survey.h"
#include "core/stereo/stereo_seabed_points.h"
#include "core/terrain/height_fit.h"
#include "core/util/error.h"

namespace seamap {
namespace {

constexpr double kVehicleDepthM = 30;  // the scene's z = 0 lies kVehicleDepthM + altitude below the surface

struct ReliefPair {
  StereoScene scene;
  StereoFrame frame;
  VehiclePose vehicle;
  double altitude_m = 0;
};

// A down-looking rig (image top to the bow, the vehicle heading north) over
// a bare seabed with `relief_m` rms relief, the left camera `altitude_m` above z = 0.
ReliefPair RenderReliefPair(double relief_m, double altitude_m, uint64_t seed) {
  StereoSceneOptions scene_options;
  scene_options.seed = seed;
  scene_options.with_object = false;
  scene_options.seabed_size_m = 8;
  scene_options.relief_rms_m = relief_m;
  ReliefPair out{StereoScene::Wellhead(scene_options), {}, {}, altitude_m};
  Rigid object_from_left = Rigid::Identity();
  object_from_left.linear().col(0) = Eigen::Vector3d(1, 0, 0);   // image right: east
  object_from_left.linear().col(1) = Eigen::Vector3d(0, -1, 0);  // image down: south
  object_from_left.linear().col(2) = Eigen::Vector3d(0, 0, -1);  // looking down
  object_from_left.translation() = Eigen::Vector3d(0.1, -0.2, altitude_m);
  const StereoCalibration rig = SimulatedStereoRig();
  StereoRenderOptions render;
  render.supersample = 1;
  const StereoImages images = RenderStereoPair(out.scene, rig, object_from_left, render, seed);
  out.frame = MakeStereoFrame("relief", images.left, images.right, rig, SiftOptions{}, StereoMatchOptions{});
  // The navigation's pose of the left camera (mount offset 0): east/north as the scene's x/y.
  out.vehicle.east_m = 0.1, out.vehicle.north_m = -0.2, out.vehicle.depth_m = kVehicleDepthM;
  out.vehicle.altitude_m = altitude_m;
  return out;
}

double Percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))];
}

TEST(StereoRelief, PairPointsLandOnTheTrueSeabed) {
  const ReliefPair pair = RenderReliefPair(0.15, 3.0, 5);
  RigMount mount;
  mount.looking = RigMount::Looking::kDown;
  const SeabedPoints points = StereoSeabedPoints(pair.frame, mount, pair.vehicle, StereoSeabedOptions{});
  ASSERT_GT(points.size(), 500u);
  std::vector<double> error_m, truth_up_m, normalised;
  for (const SeabedPoint& p : points) {
    const Eigen::Vector3d& enu = p.east_north_up_m;
    const double truth = -(kVehicleDepthM + pair.altitude_m) + pair.scene.SeabedZ(enu.x(), enu.y());
    error_m.push_back(std::abs(enu.z() - truth));
    truth_up_m.push_back(truth);
    normalised.push_back(std::abs(enu.z() - truth) / p.sigma_up_m);
    EXPECT_EQ(p.views, 2);
    EXPECT_GT(p.sigma_up_m, 0);
    EXPECT_LE(p.sigma_up_m, 0.02);
  }
  // The relief is really there: the seen heights span well over a plane's noise.
  EXPECT_GT(Percentile(truth_up_m, 0.95) - Percentile(truth_up_m, 0.05), 0.15);
  // 0.25 m baseline at 3 m, f 1040 px: 0.1 px of disparity is about 3.5 mm of
  // range (measured: median 4.3 mm, p90 15 mm, as the sigmas say).
  EXPECT_LT(Percentile(error_m, 0.5), 0.006);
  EXPECT_LT(Percentile(error_m, 0.9), 0.020);
  // The sigmas say how far off the points are (within 2 sigma for most).
  EXPECT_GT(Percentile(normalised, 0.8), 0.3);
  EXPECT_LT(Percentile(normalised, 0.8), 2.5);
}

TEST(StereoRelief, HeightModelFromOnePairFollowsTheRelief) {
  const ReliefPair pair = RenderReliefPair(0.15, 3.0, 6);
  RigMount mount;
  mount.looking = RigMount::Looking::kDown;
  const SeabedPoints points = StereoSeabedPoints(pair.frame, mount, pair.vehicle, StereoSeabedOptions{});
  HeightFitOptions fit;
  fit.cell_m = 0.1;
  HeightFitReport report;
  const HeightGrid grid = FitHeightGrid(points, {}, /*has_depth_datum=*/true, fit, &report);
  ASSERT_FALSE(grid.empty());
  double sum2 = 0, flat2 = 0;
  long cells = 0;
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      if (!std::isfinite(grid.height_m(r, c))) continue;
      const LocalXY at = grid.CellCentre(r, c);
      const double truth = -(kVehicleDepthM + pair.altitude_m) + pair.scene.SeabedZ(at.east, at.north);
      sum2 += std::pow(grid.height_m(r, c) - truth, 2);
      flat2 += std::pow(pair.scene.SeabedZ(at.east, at.north), 2);
      ++cells;
    }
  ASSERT_GT(cells, 500);  // the pair's footprint, about 2.6 x 2 m, in 10 cm cells
  const double rms = std::sqrt(sum2 / cells), flat_rms = std::sqrt(flat2 / cells);
  // Measured 10.4 mm: 10 cm cells on relief down to 0.5 m wavelengths (the
  // monocular model's target is 20 mm).
  EXPECT_LT(rms, 0.015) << "over " << cells << " cells";
  EXPECT_GT(flat_rms, 0.04);  // a plane at the mean would be this far off
}

TEST(StereoRelief, FarPointsAreLeftOutBySigma) {
  const ReliefPair pair = RenderReliefPair(0.1, 3.0, 7);
  RigMount mount;
  mount.looking = RigMount::Looking::kDown;
  StereoSeabedOptions strict;
  strict.max_sigma_up_m = 1e-4;  // tighter than any 3 m point
  EXPECT_TRUE(StereoSeabedPoints(pair.frame, mount, pair.vehicle, strict).empty());
  strict.max_sigma_up_m = 0;
  EXPECT_THROW(StereoSeabedPoints(pair.frame, mount, pair.vehicle, strict), InputError);
}

}  // namespace
}  // namespace seamap
