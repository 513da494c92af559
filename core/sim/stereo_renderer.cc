#include "core/sim/stereo_renderer.h"

#include <cmath>
#include <limits>
#include <random>

#include <opencv2/imgproc.hpp>

#include "core/util/error.h"

namespace seamap {

void StereoRenderOptions::Check() const {
  if (supersample < 1 || supersample > 4) throw InputError("", 0, "--supersample", "expected 1 to 4");
  if (!(beta_per_m >= 0 && beta_per_m < 2)) throw InputError("", 0, "--haze", "expected beta 0-2 per metre");
  if (!(noise_sigma >= 0 && noise_sigma < 50)) throw InputError("", 0, "--noise", "expected 0-50 (8-bit units)");
  if (!(blur_sigma_px >= 0 && blur_sigma_px < 10)) throw InputError("", 0, "--blur", "expected 0-10 px");
  if (!(veil >= 0 && veil <= 1)) throw InputError("", 0, "veil", "expected 0-1");
}

cv::Mat1f RenderView(const StereoScene& scene, const cv::Matx33d& K, cv::Size size, const Rigid& object_from_camera,
                     const StereoRenderOptions& options) {
  const int s = options.supersample;
  const int gw = size.width * s, gh = size.height * s;
  const double fx = K(0, 0), fy = K(1, 1), cx = K(0, 2), cy = K(1, 2);
  const Rigid camera_from_object = object_from_camera.inverse();
  // Sub-sample grid index g -> pixel coordinate (g + 0.5) / s - 0.5: centred on integer pixels.
  const auto grid_to_px = [s](int g) { return (g + 0.5) / s - 0.5; };
  const auto px_to_grid = [s](double u) { return (u + 0.5) * s - 0.5; };

  std::vector<float> depth(static_cast<size_t>(gw) * gh, std::numeric_limits<float>::infinity());
  std::vector<int32_t> id(depth.size(), -1);
  struct CamTriangle {
    Eigen::Vector3d a, b, c, n;
  };
  std::vector<CamTriangle> cam(scene.triangles.size());
  for (size_t k = 0; k < scene.triangles.size(); ++k) {
    const SceneTriangle& tri = scene.triangles[k];
    CamTriangle& c = cam[k];
    c.a = camera_from_object * tri.a;
    c.b = camera_from_object * tri.b;
    c.c = camera_from_object * tri.c;
    c.n = (c.b - c.a).cross(c.c - c.a);
    // Triangles reaching behind the camera are not clipped: the scenes keep
    // cameras above everything (checked by the caller's geometry).
    if (c.a.z() < 0.05 || c.b.z() < 0.05 || c.c.z() < 0.05) continue;
    const Eigen::Vector2d pa(fx * c.a.x() / c.a.z() + cx, fy * c.a.y() / c.a.z() + cy);
    const Eigen::Vector2d pb(fx * c.b.x() / c.b.z() + cx, fy * c.b.y() / c.b.z() + cy);
    const Eigen::Vector2d pc(fx * c.c.x() / c.c.z() + cx, fy * c.c.y() / c.c.z() + cy);
    const double area = (pb - pa).x() * (pc - pa).y() - (pb - pa).y() * (pc - pa).x();
    if (std::abs(area) < 1e-12) continue;
    const int g0x = std::max(0, static_cast<int>(std::floor(px_to_grid(std::min({pa.x(), pb.x(), pc.x()})))));
    const int g1x = std::min(gw - 1, static_cast<int>(std::ceil(px_to_grid(std::max({pa.x(), pb.x(), pc.x()})))));
    const int g0y = std::max(0, static_cast<int>(std::floor(px_to_grid(std::min({pa.y(), pb.y(), pc.y()})))));
    const int g1y = std::min(gh - 1, static_cast<int>(std::ceil(px_to_grid(std::max({pa.y(), pb.y(), pc.y()})))));
    const double n_dot_a = c.n.dot(c.a);
    const double sign = area > 0 ? 1 : -1;
    for (int gy = g0y; gy <= g1y; ++gy) {
      const double v = grid_to_px(gy);
      for (int gx = g0x; gx <= g1x; ++gx) {
        const double u = grid_to_px(gx);
        // Edge functions; the half-open rule on ties keeps shared edges covered once.
        const double w0 = sign * ((pb.x() - pa.x()) * (v - pa.y()) - (pb.y() - pa.y()) * (u - pa.x()));
        const double w1 = sign * ((pc.x() - pb.x()) * (v - pb.y()) - (pc.y() - pb.y()) * (u - pb.x()));
        const double w2 = sign * ((pa.x() - pc.x()) * (v - pc.y()) - (pa.y() - pc.y()) * (u - pc.x()));
        if (w0 < 0 || w1 < 0 || w2 < 0) continue;
        const Eigen::Vector3d ray((u - cx) / fx, (v - cy) / fy, 1);
        const double z = n_dot_a / c.n.dot(ray);  // exact ray-plane depth
        const size_t at = static_cast<size_t>(gy) * gw + gx;
        if (z > 0 && z < depth[at]) {
          depth[at] = static_cast<float>(z);
          id[at] = static_cast<int32_t>(k);
        }
      }
    }
  }

  cv::Mat1f image(size, 0.0f);
  const double inv_samples = 1.0 / (s * s);
  for (int y = 0; y < size.height; ++y) {
    float* row = image[y];
    for (int x = 0; x < size.width; ++x) {
      double sum = 0;
      for (int j = 0; j < s; ++j)
        for (int i = 0; i < s; ++i) {
          const int gx = x * s + i, gy = y * s + j;
          const size_t at = static_cast<size_t>(gy) * gw + gx;
          if (id[at] < 0) {
            sum += 255 * options.veil;
            continue;
          }
          const Eigen::Vector3d ray((grid_to_px(gx) - cx) / fx, (grid_to_px(gy) - cy) / fy, 1);
          const Eigen::Vector3d p_cam = ray * depth[at];
          const CamTriangle& c = cam[id[at]];
          const double r = p_cam.norm();
          const double lambert = std::abs(c.n.dot(p_cam)) / (c.n.norm() * r);
          const double albedo = scene.Albedo(scene.triangles[id[at]].material, object_from_camera * p_cam);
          const double j_radiance = albedo * (options.ambient + options.lamp * lambert / (r * r));
          const double t = std::exp(-options.beta_per_m * r);
          sum += 255 * (j_radiance * t + options.veil * (1 - t));
        }
      row[x] = static_cast<float>(sum * inv_samples);
    }
  }
  if (options.blur_sigma_px > 0) cv::GaussianBlur(image, image, cv::Size(), options.blur_sigma_px);
  return image;
}

StereoImages RenderStereoPair(const StereoScene& scene, const StereoCalibration& calibration,
                              const Rigid& object_from_left, const StereoRenderOptions& options, uint64_t noise_seed) {
  options.Check();
  for (const auto* d : {&calibration.D1, &calibration.D2})
    for (double k : *d)
      if (k != 0) throw InputError("", 0, "D1/D2", "the stereo renderer draws no lens distortion");
  // p_right = R p_left + T, so left_from_right = [R^T | -R^T T].
  const Rigid object_from_right = object_from_left * Rigid(calibration.LeftFromRight());
  std::mt19937_64 rng(noise_seed);
  std::normal_distribution<float> noise(0, static_cast<float>(options.noise_sigma));
  const auto finish = [&](const cv::Mat1f& f) {
    cv::Mat1f noisy = f.clone();
    if (options.noise_sigma > 0)
      for (auto it = noisy.begin(); it != noisy.end(); ++it) *it += noise(rng);
    cv::Mat out;
    noisy.convertTo(out, CV_8U);  // rounds and saturates
    return out;
  };
  StereoImages images;
  images.left = finish(RenderView(scene, calibration.K1, calibration.image_size, object_from_left, options));
  images.right = finish(RenderView(scene, calibration.K2, calibration.image_size, object_from_right, options));
  return images;
}

}  // namespace seamap
