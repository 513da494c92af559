#include "core/trajectory/seabed_tracks.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "core/util/error.h"
#include "tests/core/trajectory/synthetic_seabed.h"

namespace seamap {
namespace {

using testing_seabed::Lawnmower;
using testing_seabed::Relief;
using testing_seabed::Scene;

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
}

Scene ReliefScene(const Relief& relief, int lanes, double lane_length_m) {
  Scene scene;
  scene.poses = Lawnmower(relief, lanes, lane_length_m, 0.9, 0.15);
  scene.ScatterOnRelief(relief, -2, (lanes - 1) * 0.9 + 2, -2, lane_length_m + 2, 150);
  return scene;
}

SeabedTracks TrackScene(const Scene& scene, const TrackOptions& options, TrackReport* report) {
  return BuildSeabedTracks(
      scene.poses, scene.camera, [&](int i) { return scene.FeaturesOf(i); }, options, report);
}

TEST(SeabedTracks, TriangulatesMultiViewTracksOnReliefWithinMillimetres) {
  const Relief relief(0.3, 11);
  const Scene scene = ReliefScene(relief, 3, 4.0);
  TrackReport report;
  const SeabedTracks out = TrackScene(scene, TrackOptions(), &report);
  ASSERT_EQ(out.points.size(), out.tracks.size());
  ASSERT_GT(report.pairs, 0);
  // Most scene points under the survey become seabed points.
  EXPECT_GT(out.points.size(), 1000u) << "matches " << report.matches << " tracks " << report.tracks;
  std::vector<double> error, standardised, views;
  for (size_t k = 0; k < out.tracks.size(); ++k) {
    const SeabedTrack& t = out.tracks[k];
    std::set<int> frames;
    for (const TrackObservation& o : t.observations) frames.insert(o.frame);
    ASSERT_EQ(frames.size(), t.observations.size()) << "one observation per frame";
    ASSERT_GE(t.observations.size(), 2u);
    const Eigen::Vector3d& p = out.points[k].east_north_up_m;
    const double e = p.z() - relief.Up(p.x(), p.y());
    error.push_back(std::fabs(e));
    standardised.push_back(std::fabs(e) / out.points[k].sigma_up_m);
    views.push_back(t.observations.size());
  }
  EXPECT_LT(Quantile(error, 0.5), 0.003);
  EXPECT_LT(Quantile(error, 0.95), 0.012);
  EXPECT_GT(Quantile(views, 0.5), 3);
  // The sigma is honest: |error| / sigma about normal.
  const double within2 = std::count_if(standardised.begin(), standardised.end(), [](double s) { return s < 2; }) /
                         static_cast<double>(standardised.size());
  EXPECT_GT(within2, 0.85);
  EXPECT_LT(within2, 0.995);
}

TEST(SeabedTracks, HoldsOnlyTheFramesThatCanStillOverlap) {
  const Relief relief(0.1, 3);
  Scene scene;
  scene.poses = Lawnmower(relief, 1, 20.0, 0.9, 0.15);  // one lane, 134 frames
  scene.ScatterOnRelief(relief, -2, 2, -2, 22, 40);
  TrackReport report;
  const SeabedTracks out = TrackScene(scene, TrackOptions(), &report);
  EXPECT_GT(out.points.size(), 200u);
  EXPECT_LT(report.peak_frames_in_memory, 20) << "frames held at once on a straight lane";
  EXPECT_GT(report.peak_frames_in_memory, 2);
}

TEST(SeabedTracks, RejectsFalseMatchesFishAndParticles) {
  const Relief relief(0.3, 5);
  Scene scene = ReliefScene(relief, 3, 4.0);
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> ue(-0.5, 2.3), un(0, 4);
  const size_t seabed_points = scene.points.size();
  // Fish: swimming 3 cm a frame, 0.4 m above the seabed.
  for (int k = 0; k < 200; ++k) {
    const double e = ue(rng), n = un(rng);
    scene.points.push_back({{e, n, relief.Up(e, n) + 0.4}, scene.RandomDescriptor(&rng), 0.03});
  }
  // Particles: still, 1.7 m above the seabed (beyond the relief allowed).
  for (int k = 0; k < 200; ++k) {
    const double e = ue(rng), n = un(rng);
    scene.points.push_back({{e, n, relief.Up(e, n) + 1.7}, scene.RandomDescriptor(&rng)});
  }
  // Repeated texture: 300 seabed points share another's descriptor.
  for (int k = 0; k < 300; ++k) scene.points[k + 300].descriptor = scene.points[k].descriptor;
  TrackReport report;
  const SeabedTracks out = TrackScene(scene, TrackOptions(), &report);
  EXPECT_GT(out.points.size(), 800u);
  long far = 0, particles = 0;
  for (const SeabedPoint& p : out.points) {
    const double error = p.east_north_up_m.z() - relief.Up(p.east_north_up_m.x(), p.east_north_up_m.y());
    far += std::fabs(error) > 0.05 && std::fabs(error) > 4 * p.sigma_up_m;
    particles += error > 1.0;
  }
  // A fish seen from two survey lines can look like a still point (its
  // motion along the epipolar line): a few get through, for the height fit
  // to reject against their neighbourhood (height_fit_test, seabed_terrain_test).
  EXPECT_LT(far, static_cast<long>(0.02 * out.points.size()))
      << "of " << out.points.size() << " from " << seabed_points << " seabed points";
  // Particles 1.7 m up are beyond --max-relief of the seabed under most frames.
  EXPECT_LT(particles, 10) << "of 200";
}

TEST(SeabedTracks, TriangulateTrackKeepsGoodRaysAndRejectsBadOnes) {
  const CameraModel camera = testing_seabed::SmallCamera();
  VehiclePose a, b;
  a.depth_m = b.depth_m = 10;
  a.altitude_m = b.altitude_m = 2;
  b.north_m = 0.5;
  const std::vector<TrackCamera> views = {TrackCameraOf(camera, a), TrackCameraOf(camera, b)};
  EXPECT_NEAR(views[0].centre_m.z(), -10, 1e-12);
  EXPECT_NEAR(views[0].seabed_up_m, -12, 1e-12);
  auto track_of = [&](const Eigen::Vector3d& point) {
    SeabedTrack t;
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d px;
      EXPECT_TRUE(ProjectToIdeal(camera, views[k], point, &px));
      t.observations.push_back({k, 0, cv::Point2f(static_cast<float>(px.x()), static_cast<float>(px.y()))});
    }
    return t;
  };
  TrackOptions options;
  std::string why;
  SeabedTrack two = track_of({0.1, 0.3, -11.8});
  EXPECT_FALSE(TriangulateTrack(camera, views, options, &two, &why)) << "three views by default";
  EXPECT_EQ(why, "views");
  options.min_views = 2;
  SeabedTrack good = track_of({0.1, 0.3, -11.8});
  ASSERT_TRUE(TriangulateTrack(camera, views, options, &good, &why)) << why;
  EXPECT_NEAR(good.east_north_up_m.z(), -11.8, 1e-3);
  EXPECT_GT(good.sigma_up_m, 0);
  EXPECT_LT(good.sigma_up_m, 0.02);
  SeabedTrack fish = track_of({0.1, 0.3, -10.3});  // 1.7 m above the expected seabed
  EXPECT_FALSE(TriangulateTrack(camera, views, options, &fish, &why));
  EXPECT_EQ(why, "seabed");
  SeabedTrack off = track_of({0.1, 0.3, -11.8});
  off.observations[1].ideal_px.x += 6;  // not the same point
  EXPECT_FALSE(TriangulateTrack(camera, views, options, &off, &why));
  EXPECT_EQ(why, "reprojection");
  options.min_ray_angle_deg = 30;
  SeabedTrack narrow = track_of({0.1, 0.3, -11.8});
  EXPECT_FALSE(TriangulateTrack(camera, views, options, &narrow, &why));
  EXPECT_EQ(why, "ray angle");
}

TEST(SeabedTracks, OptionsNameTheBadOne) {
  TrackOptions o;
  o.max_relief_m = -1;
  try {
    o.Check();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--max-relief");
  }
  o = TrackOptions();
  o.ratio = 1.5;
  EXPECT_THROW(o.Check(), InputError);
}

}  // namespace
}  // namespace seamap
