#include "core/sim/stereo_renderer.h"

#include <gtest/gtest.h>

#include "core/sim/stereo_survey.h"

namespace seamap {
namespace {

// A 3 cm square of constant albedo at (x, y, 0) on an empty background, lit evenly.
StereoScene Square(double x, double y) {
  StereoSceneOptions untextured;
  untextured.object_texture = 0;  // constant albedo: the centroid is the square's centre
  StereoScene scene = StereoScene::Plane(untextured);
  scene.triangles.clear();
  const double h = 0.015;
  const Eigen::Vector3d a(x - h, y - h, 0), b(x + h, y - h, 0), c(x + h, y + h, 0), d(x - h, y + h, 0);
  scene.triangles.push_back({a, b, c, SceneMaterial::kValve});
  scene.triangles.push_back({a, c, d, SceneMaterial::kValve});
  return scene;
}

cv::Point2d Centroid(const cv::Mat1f& image, float background) {
  double sx = 0, sy = 0, sw = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const double w = image(y, x) - background;
      if (std::abs(w) < 1e-3) continue;
      sx += w * x, sy += w * y, sw += w;
    }
  return {sx / sw, sy / sw};
}

TEST(StereoRenderer, ADotIsDrawnWhereItProjectsInBothCameras) {
  const StereoCalibration rig = SimulatedStereoRig();
  StereoRenderOptions options;
  options.lamp = 0, options.ambient = 1, options.beta_per_m = 0, options.noise_sigma = 0, options.supersample = 3;
  // Camera 3.2 m above, looking down, slightly turned; the dot off-centre at a sub-pixel position.
  Rigid object_from_left = Rigid::Identity();
  const double h = 0.2;
  object_from_left.linear() << std::cos(h), std::sin(h), 0, std::sin(h), -std::cos(h), 0, 0, 0, -1;
  object_from_left.translation() = Eigen::Vector3d(0.05, -0.02, 3.2);
  const Eigen::Vector3d dot(0.4137, 0.2219, 0);
  const StereoScene scene = Square(dot.x(), dot.y());
  const float background = static_cast<float>(255 * options.veil);

  const cv::Mat1f left = RenderView(scene, rig.K1, rig.image_size, object_from_left, options);
  const cv::Point2d expected_left = rig.ProjectRaw(object_from_left.inverse() * dot, false);
  const cv::Point2d got_left = Centroid(left, background);
  EXPECT_LT(cv::norm(got_left - expected_left), 0.05) << got_left << " vs " << expected_left;

  const Rigid object_from_right = object_from_left * Rigid(rig.LeftFromRight());
  const cv::Mat1f right = RenderView(scene, rig.K2, rig.image_size, object_from_right, options);
  const cv::Point2d expected_right = rig.ProjectRaw(object_from_left.inverse() * dot, true);
  const cv::Point2d got_right = Centroid(right, background);
  EXPECT_LT(cv::norm(got_right - expected_right), 0.05) << got_right << " vs " << expected_right;
  // Rectified, the two images' rows agree.
  const double row_l = rig.RectifyLeft({got_left})[0].y, row_r = rig.RectifyRight({got_right})[0].y;
  EXPECT_NEAR(row_l, row_r, 0.05);
  // Disparity says the depth: f B / Z.
  EXPECT_NEAR(rig.RectifyLeft({got_left})[0].x - rig.RectifyRight({got_right})[0].x, rig.rig.f * 0.25 / 3.2, 0.1);
}

TEST(StereoScene, TheWellheadVariesWithTheSeedAndHasCheckPointsOnTheObject) {
  StereoSceneOptions o;
  const StereoScene a = StereoScene::Wellhead(o);
  o.seed = 2;
  const StereoScene b = StereoScene::Wellhead(o);
  EXPECT_NE(a.layout, b.layout);
  EXPECT_GE(a.check_points.size(), 12u);
  EXPECT_GT(a.top_z_m, 2.7);
  for (const auto& [name, p] : a.check_points) {
    EXPECT_LE(std::abs(p.x()), a.footprint_m / 2 + 0.1) << name;
    EXPECT_GT(p.z(), 0.2) << name;
  }
}

}  // namespace
}  // namespace seamap
