#include "core/trajectory/two_view.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include <Eigen/Geometry>

namespace seamap {
namespace {

const cv::Matx33d kK(620, 0, 347.5, 0, 620, 259.5, 0, 0, 1);
const cv::Size kSize(696, 520);

Eigen::Matrix3d Rotation(double rx_deg, double ry_deg, double rz_deg) {
  const double d = M_PI / 180;
  return (Eigen::AngleAxisd(rz_deg * d, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(ry_deg * d, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rx_deg * d, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

// Seabed points seen by camera 1 (tilted `tilt_deg` about x) at `height_m`
// from the plane, with `relief` (a share of the height) of random bumps; then
// camera 2 moved by `c` (camera-1 axes, metres) and turned by `r21`.
struct Pair {
  std::vector<cv::Point2d> p1, p2;
  PairGeometry geometry;
  Pair(double tilt_deg, double height_m, double relief, const Eigen::Vector3d& c, const Eigen::Matrix3d& r21,
       double noise_px, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.45, 0.45), bump(-relief, relief);
    std::normal_distribution<double> noise(0, noise_px);
    const Eigen::Matrix3d tilt = Rotation(tilt_deg, 0, 0);
    const Eigen::Vector3d normal = tilt * Eigen::Vector3d::UnitZ();  // camera-1 axes, towards the seabed
    auto project = [](const Eigen::Vector3d& x) {
      return cv::Point2d(kK(0, 0) * x.x() / x.z() + kK(0, 2), kK(1, 1) * x.y() / x.z() + kK(1, 2));
    };
    while (p1.size() < 600) {
      // A ray through the image, to the plane, moved along the normal by the relief.
      const Eigen::Vector3d ray(u(rng) * 1.1, u(rng) * 0.84, 1);
      const double depth = height_m / normal.dot(ray);
      const Eigen::Vector3d x1 = ray * depth + normal * (bump(rng) * height_m);
      const Eigen::Vector3d x2 = r21 * (x1 - c);
      if (x2.z() <= 0.1) continue;
      const cv::Point2d a = project(x1), b = project(x2);
      if (b.x < 0 || b.y < 0 || b.x >= kSize.width || b.y >= kSize.height) continue;
      p1.push_back(a + cv::Point2d(noise(rng), noise(rng)));
      p2.push_back(b + cv::Point2d(noise(rng), noise(rng)));
    }
    geometry.K = kK;
    geometry.image_size = kSize;
    geometry.cam2_from_cam1_ahrs = r21;
    geometry.seabed_normal_cam1 = normal;
    geometry.height_m = height_m;
  }
};

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180 / M_PI;
}

TEST(TwoView, AFlatSeabedChoosesTheHomographyAndGivesTheMetricMotion) {
  // Each pair within 1.5 % in scale and 1 degree in direction; on average
  // within 0.5 % (what accumulates into drift is the bias).
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> step(-0.08, 0.08);
  double scale_sum = 0;
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector3d c(step(rng), 0.1 + step(rng) / 4, step(rng) / 4);
    const Eigen::Matrix3d r21 = Rotation(step(rng) * 10, step(rng) * 10, step(rng) * 20);
    const Pair pair(10, 2.0, 0.0, c, r21, 0.3, trial);
    ModelSwitch models;
    const TwoViewMotion m = models.Next(pair.p1, pair.p2, pair.geometry);
    ASSERT_EQ(m.model, MotionModel::kHomography) << trial << ": " << m.failure;
    EXPECT_LT(AngleDeg(m.displacement_cam1_m, c), 1.0) << trial;
    EXPECT_NEAR(m.displacement_cam1_m.norm() / c.norm(), 1.0, 0.015) << trial;
    scale_sum += m.displacement_cam1_m.norm() / c.norm();
    EXPECT_LT(m.rotation_error_deg, 0.2);
    EXPECT_GT(m.cheirality, 0.99);
  }
  EXPECT_NEAR(scale_sum / 10, 1.0, 0.005);
}

TEST(TwoView, ReliefChoosesTheEssentialMatrixAndScalesItByThePlane) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> step(-0.08, 0.08);
  int essential = 0;
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Vector3d c(step(rng), 0.12 + step(rng) / 4, step(rng) / 4);
    const Eigen::Matrix3d r21 = Rotation(step(rng) * 10, step(rng) * 10, step(rng) * 20);
    const Pair pair(5, 2.0, 0.4, c, r21, 0.3, 100 + trial);
    // Independent bumps on every point: no seabed below the altimeter to
    // speak of, the altitude is the plane's (the pre-relief scale).
    TwoViewOptions options;
    options.scale_at_nadir = false;
    ModelSwitch models(options);
    const TwoViewMotion m = models.Next(pair.p1, pair.p2, pair.geometry);
    ASSERT_NE(m.model, MotionModel::kNone) << m.failure;
    essential += m.model == MotionModel::kEssential;
    if (m.model != MotionModel::kEssential) continue;
    EXPECT_LT(AngleDeg(m.displacement_cam1_m, c), 1.0) << trial;
    // Bumps of +-40 % around the plane leave no plane to fit: the median
    // distance along the expected normal, biased by which bumps both views see.
    EXPECT_NEAR(m.displacement_cam1_m.norm() / c.norm(), 1.0, 0.1) << trial;
  }
  EXPECT_GE(essential, 8);
}

TEST(TwoView, ARotationTheAhrsDoesNotSeeFailsTheModel) {
  const Eigen::Vector3d c(0.0, 0.1, 0.0);
  const Eigen::Matrix3d r21 = Rotation(0, 0, 8);
  Pair pair(5, 2.0, 0.0, c, r21, 0.3, 7);
  pair.geometry.cam2_from_cam1_ahrs = Eigen::Matrix3d::Identity();  // the AHRS says: no turn
  ModelSwitch models;
  const TwoViewMotion m = models.Next(pair.p1, pair.p2, pair.geometry);
  EXPECT_EQ(m.model, MotionModel::kNone);
  EXPECT_EQ(models.in_use(), MotionModel::kNone);
}

TEST(TwoView, TheModelInUseStaysWhileItPasses) {
  // Flat pairs choose H; a pair with relief where H fails switches to E,
  // which then stays for a following pair that either model explains
  // (persistent, as the paper), though the counts would choose H there.
  ModelSwitch models;
  const Eigen::Vector3d c(0.01, 0.1, 0.0);
  const Eigen::Matrix3d r21 = Rotation(1, -1, 2);
  EXPECT_EQ(models
                .Next(Pair(10, 2, 0, c, r21, 0.3, 1).p1, Pair(10, 2, 0, c, r21, 0.3, 1).p2,
                      Pair(10, 2, 0, c, r21, 0.3, 1).geometry)
                .model,
            MotionModel::kHomography);
  const Pair rough(5, 2, 0.5, c, r21, 0.3, 2);
  const TwoViewMotion switched = models.Next(rough.p1, rough.p2, rough.geometry);
  EXPECT_EQ(switched.model, MotionModel::kEssential) << switched.failure;
  const Pair mild(10, 2, 0.05, c, r21, 0.3, 3);
  ASSERT_EQ(EstimateWithModel(MotionModel::kHomography, mild.p1, mild.p2, mild.geometry, {}).failure, "");
  EXPECT_EQ(models.Next(mild.p1, mild.p2, mild.geometry).model, MotionModel::kEssential);
  const Pair flat(10, 2, 0, c, r21, 0.3, 5);
  // Garbage: both fail, and the next pair chooses again by counts.
  std::vector<cv::Point2d> a = flat.p1, b = flat.p2;
  std::mt19937 rng(4);
  std::shuffle(b.begin(), b.end(), rng);
  EXPECT_EQ(models.Next(a, b, flat.geometry).model, MotionModel::kNone);
  EXPECT_EQ(models.Next(flat.p1, flat.p2, flat.geometry).model, MotionModel::kHomography);
}

// A smooth seabed whose height under the altimeter is not the view's mean:
// camera 1 tilted `tilt_deg` about x, the seabed at `mean_m` along the normal
// less `bump_m` * cos(2 pi x / 2 m) cos(2 pi y / 3 m) (lateral metres from
// the camera), a share `wrong` of the matches random. The altimeter sits at
// `altimeter` (camera-1 axes) and measures the range below it.
struct ReliefPair {
  std::vector<cv::Point2d> p1, p2;
  PairGeometry geometry;
  ReliefPair(double tilt_deg, double mean_m, double bump_m, const Eigen::Vector3d& altimeter, const Eigen::Vector3d& c,
             const Eigen::Matrix3d& r21, double noise_px, double wrong, uint32_t seed, double beam_deg = 0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.45, 0.45), unit(0, 1), anywhere(0, 1);
    std::normal_distribution<double> noise(0, noise_px);
    const Eigen::Vector3d normal = Rotation(tilt_deg, 0, 0) * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d across_u = normal.unitOrthogonal(), across_v = normal.cross(across_u);
    auto seabed = [&](const Eigen::Vector3d& x) {  // distance along the normal below lateral x
      const double a = across_u.dot(x), b = across_v.dot(x);
      return mean_m - bump_m * std::cos(2 * M_PI * a / 2.0) * std::cos(2 * M_PI * b / 3.0);
    };
    auto project = [](const Eigen::Vector3d& x) {
      return cv::Point2d(kK(0, 0) * x.x() / x.z() + kK(0, 2), kK(1, 1) * x.y() / x.z() + kK(1, 2));
    };
    while (p1.size() < 800) {
      const Eigen::Vector3d ray(u(rng) * 1.1, u(rng) * 0.84, 1);
      double depth = mean_m / normal.dot(ray);
      for (int k = 0; k < 50; ++k) depth = seabed(ray * depth) / normal.dot(ray);  // the ray meets the seabed
      const Eigen::Vector3d x1 = ray * depth;
      const Eigen::Vector3d x2 = r21 * (x1 - c);
      if (x2.z() <= 0.1) continue;
      const cv::Point2d a = project(x1), b = project(x2);
      if (b.x < 0 || b.y < 0 || b.x >= kSize.width || b.y >= kSize.height) continue;
      p1.push_back(a + cv::Point2d(noise(rng), noise(rng)));
      p2.push_back(unit(rng) < wrong ? cv::Point2d(anywhere(rng) * kSize.width, anywhere(rng) * kSize.height)
                                     : b + cv::Point2d(noise(rng), noise(rng)));
    }
    geometry.K = kK;
    geometry.image_size = kSize;
    geometry.cam2_from_cam1_ahrs = r21;
    geometry.seabed_normal_cam1 = normal;
    geometry.altimeter_cam1_m = altimeter;
    // The altimeter's range: straight down, or a DVL's mean vertical range
    // over its four beams `beam_deg` off the normal; height_m is the
    // camera's, the altimeter's offset along the normal added.
    double range = seabed(altimeter) - normal.dot(altimeter);
    if (beam_deg > 0) {
      range = 0;
      const double tilt = beam_deg * M_PI / 180;
      for (int k = 0; k < 4; ++k) {
        const double azimuth = (45 + 90 * k) * M_PI / 180;
        const Eigen::Vector3d beam =
            std::cos(tilt) * normal + std::sin(tilt) * (std::cos(azimuth) * across_u + std::sin(azimuth) * across_v);
        double along = seabed(altimeter) / normal.dot(beam);
        for (int i = 0; i < 50; ++i)
          along = (seabed(altimeter + along * beam) - normal.dot(altimeter)) / normal.dot(beam);
        range += along * normal.dot(beam) / 4;
        geometry.altimeter_beams_cam1.push_back(beam);
      }
    }
    geometry.height_m = range + normal.dot(altimeter);
  }
};

TEST(TwoView, OnReliefTheAltitudeScalesThePointsBelowTheAltimeter) {
  // A 0.25 m high crest under the vehicle at 2 m: the plane through the whole
  // view sits deeper than the seabed the altimeter measures, so the plane's
  // scale is long by several per cent on every pair; the points near the
  // footprint give it without that bias. Per pair the scale is noisy (0.3 px
  // of noise on a baseline of 6 % of the range: E's rotation is a few
  // hundredths of a degree off, which moves the triangulated depths by per
  // cents), so the bound is on the mean.
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> step(-0.08, 0.08);
  double sum_nadir = 0, sum_plane = 0;
  const int trials = 16;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::Vector3d c(step(rng), 0.12 + step(rng) / 4, step(rng) / 4);
    const Eigen::Matrix3d r21 = Rotation(step(rng) * 10, step(rng) * 10, step(rng) * 20);
    const ReliefPair pair(5, 2.0, 0.25, Eigen::Vector3d::Zero(), c, r21, 0.3, 0.1, 300 + trial);
    TwoViewOptions options;
    const TwoViewMotion m = EstimateWithModel(MotionModel::kEssential, pair.p1, pair.p2, pair.geometry, options);
    ASSERT_EQ(m.failure, "") << trial;
    EXPECT_LT(AngleDeg(m.displacement_cam1_m, c), 2.0) << trial;
    EXPECT_NEAR(m.displacement_cam1_m.norm() / c.norm(), 1.0, 0.08) << trial;
    sum_nadir += m.displacement_cam1_m.norm() / c.norm();
    options.scale_at_nadir = false;
    const TwoViewMotion plane = EstimateWithModel(MotionModel::kEssential, pair.p1, pair.p2, pair.geometry, options);
    ASSERT_EQ(plane.failure, "") << trial;
    sum_plane += plane.displacement_cam1_m.norm() / c.norm();
  }
  std::printf("mean scale: %.4f at the footprint, %.4f from the plane\n", sum_nadir / trials, sum_plane / trials);
  EXPECT_NEAR(sum_nadir / trials, 1.0, 0.02);
  EXPECT_GT(std::fabs(sum_plane / trials - 1.0), 0.05);  // what the plane did: the test can tell them apart
}

TEST(TwoView, TheAltitudeIsMeasuredBelowTheAltimeterNotTheCamera) {
  // The altimeter 0.4 m aft of the camera, over the crest's flank: its range
  // differs from the camera's own by ~0.1 m; the scale still comes out right
  // on average (single pairs are noisy, see above).
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> step(-0.05, 0.05);
  const Eigen::Vector3d altimeter(0.0, -0.4, 0.05);
  double sum = 0, sum_ignored = 0;
  const int trials = 8;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::Vector3d c(step(rng), 0.12 + step(rng) / 4, step(rng) / 4);
    const Eigen::Matrix3d r21 = Rotation(step(rng) * 10, step(rng) * 10, step(rng) * 20);
    const ReliefPair pair(0, 2.0, 0.25, altimeter, c, r21, 0.3, 0.0, 41 + trial);
    const TwoViewMotion m = EstimateWithModel(MotionModel::kEssential, pair.p1, pair.p2, pair.geometry, {});
    ASSERT_EQ(m.failure, "");
    sum += m.displacement_cam1_m.norm() / c.norm();
    PairGeometry ignored = pair.geometry;
    ignored.altimeter_cam1_m.setZero();  // as if below the camera: off by the flank's height
    sum_ignored +=
        EstimateWithModel(MotionModel::kEssential, pair.p1, pair.p2, ignored, {}).displacement_cam1_m.norm() / c.norm();
  }
  EXPECT_NEAR(sum / trials, 1.0, 0.02);
  EXPECT_GT(std::fabs(sum_ignored / trials - 1.0), 0.04);
}

TEST(TwoView, ADvlsFourBeamsAreCastOntoTheTriangulatedSeabed) {
  // A DVL's altitude averages four beams 30 degrees off the vertical (its
  // footprints near the image's edges), not the seabed below it: over the
  // crest they read ~0.2 m more than straight down. Modelled, the scale is
  // right on average; taken as the range straight down, ~10 % short.
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> step(-0.05, 0.05);
  double sum_beams = 0, sum_down = 0;
  const int trials = 12;
  for (int trial = 0; trial < trials; ++trial) {
    const Eigen::Vector3d c(step(rng), 0.12 + step(rng) / 4, step(rng) / 4);
    const Eigen::Matrix3d r21 = Rotation(step(rng) * 10, step(rng) * 10, step(rng) * 20);
    const ReliefPair pair(3, 2.0, 0.2, Eigen::Vector3d::Zero(), c, r21, 0.3, 0.05, 500 + trial, 30);
    const TwoViewMotion m = EstimateWithModel(MotionModel::kEssential, pair.p1, pair.p2, pair.geometry, {});
    ASSERT_EQ(m.failure, "") << trial;
    sum_beams += m.displacement_cam1_m.norm() / c.norm();
    PairGeometry down = pair.geometry;
    down.altimeter_beams_cam1.clear();
    sum_down +=
        EstimateWithModel(MotionModel::kEssential, pair.p1, pair.p2, down, {}).displacement_cam1_m.norm() / c.norm();
  }
  std::printf("mean scale: %.4f with the beams, %.4f straight down\n", sum_beams / trials, sum_down / trials);
  EXPECT_NEAR(sum_beams / trials, 1.0, 0.025);
  EXPECT_GT(std::fabs(sum_down / trials - 1.0), 0.05);
}

TEST(SeabedDistanceAt, FollowsTheLocalSeabedAndNeedsPoints) {
  // Points on a plane tilted 20 degrees from the normal: the distance at a
  // footprint 0.5 m aside is the plane's there, not the points' median.
  std::vector<Eigen::Vector3d> points;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  const double slope = std::tan(20 * M_PI / 180);
  for (int k = 0; k < 400; ++k) {
    const double x = u(rng), y = u(rng);
    points.emplace_back(x, y, 2.0 + slope * x + (k % 10 == 0 ? u(rng) : 0.0));  // a tenth off the seabed
  }
  const auto at = SeabedDistanceAt(points, Eigen::Vector3d::UnitZ(), Eigen::Vector3d(0.5, 0, 7), 0.2);
  ASSERT_TRUE(at);
  EXPECT_NEAR(*at, 2.0 + slope * 0.5, 0.002);
  EXPECT_FALSE(SeabedDistanceAt(std::vector<Eigen::Vector3d>(points.begin(), points.begin() + 15),
                                Eigen::Vector3d::UnitZ(), Eigen::Vector3d::Zero(), 0.2));
}

TEST(FitPlane, FindsTheSeabedAmongOutliers) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const Eigen::Vector3d normal = Rotation(10, -4, 0) * Eigen::Vector3d::UnitZ();
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < 200; ++k) {
    Eigen::Vector3d p(u(rng), u(rng), 0);
    p = p - normal * normal.dot(p) + normal * 2.0;  // on the plane n.x = 2
    if (k % 5 == 0) p += normal * u(rng);           // a fifth off it
    points.push_back(p);
  }
  const auto plane = FitPlane(points, 0.01);
  ASSERT_TRUE(plane);
  EXPECT_NEAR(plane->distance, 2.0, 0.004);  // 0.2 %
  EXPECT_GT(plane->normal.dot(normal), 0.9999);
  EXPECT_FALSE(FitPlane(std::vector<Eigen::Vector3d>(points.begin(), points.begin() + 10), 0.01));
}

}  // namespace
}  // namespace seamap
