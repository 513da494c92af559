#include "core/stereo/icp_baseline.h"

#include <chrono>
#include <cmath>
#include <random>

#include <opencv2/flann.hpp>
#include <opencv2/surface_matching.hpp>
#include <opencv2/surface_matching/ppf_helpers.hpp>

namespace seamap {
namespace {

cv::Mat WithNormals(const std::vector<Eigen::Vector3d>& points, int neighbours, const Eigen::Vector3d& viewpoint) {
  cv::Mat pc(static_cast<int>(points.size()), 3, CV_32F);
  for (size_t k = 0; k < points.size(); ++k)
    for (int i = 0; i < 3; ++i) pc.at<float>(static_cast<int>(k), i) = static_cast<float>(points[k][i]);
  cv::Mat with_normals;
  cv::ppf_match_3d::computeNormalsPC3d(pc, with_normals, neighbours, true,
                                       cv::Vec3f(static_cast<float>(viewpoint.x()), static_cast<float>(viewpoint.y()),
                                                 static_cast<float>(viewpoint.z())));
  return with_normals;
}

}  // namespace

std::vector<Eigen::Vector3d> OffDominantPlane(const std::vector<Eigen::Vector3d>& points, double plane_m,
                                              double off_plane_m) {
  if (points.size() < 3) return points;
  std::mt19937 rng(7);  // fixed: the same cloud always splits the same way
  std::uniform_int_distribution<size_t> pick(0, points.size() - 1);
  Eigen::Vector3d best_normal = Eigen::Vector3d::Zero();
  double best_offset = 0;
  size_t best_count = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const Eigen::Vector3d a = points[pick(rng)], b = points[pick(rng)], c = points[pick(rng)];
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-9) continue;
    const Eigen::Vector3d normal = n.normalized();
    const double offset = normal.dot(a);
    size_t count = 0;
    for (const Eigen::Vector3d& p : points) count += std::abs(normal.dot(p) - offset) <= plane_m;
    if (count > best_count) best_count = count, best_normal = normal, best_offset = offset;
  }
  if (3 * best_count < points.size()) return points;
  std::vector<Eigen::Vector3d> off;
  for (const Eigen::Vector3d& p : points)
    if (std::abs(best_normal.dot(p) - best_offset) > off_plane_m) off.push_back(p);
  return off;
}

IcpRegistration RegisterIcp(const std::vector<Eigen::Vector3d>& model_all,
                            const std::vector<Eigen::Vector3d>& scene_all, const IcpOptions& options) {
  IcpRegistration out;
  const std::vector<Eigen::Vector3d> model_structure =
      OffDominantPlane(model_all, options.plane_m, options.off_plane_m);
  const std::vector<Eigen::Vector3d> scene_structure =
      OffDominantPlane(scene_all, options.plane_m, options.off_plane_m);
  out.structure = static_cast<int>(scene_structure.size());
  if (model_structure.size() < 10 || scene_structure.size() < 10) return out;
  // Model normals towards the first overview camera (the frame's origin), scene normals towards the camera.
  const cv::Mat src = WithNormals(model_structure, options.normal_neighbours, Eigen::Vector3d::Zero());
  const cv::Mat dst = WithNormals(scene_structure, options.normal_neighbours, Eigen::Vector3d::Zero());
  Eigen::Vector3d model_centre = Eigen::Vector3d::Zero(), scene_centre = Eigen::Vector3d::Zero();
  for (const auto& p : model_structure) model_centre += p / model_structure.size();
  for (const auto& p : scene_structure) scene_centre += p / scene_structure.size();
  std::vector<cv::ppf_match_3d::Pose3DPtr> seeds;
  for (int k = 0; k < options.seeds; ++k) {
    // camera_from_object seeds: a turn about the viewing axis, centroids aligned.
    const Eigen::Matrix3d r = Eigen::AngleAxisd(2 * M_PI * k / options.seeds, Eigen::Vector3d::UnitZ()).matrix();
    const Eigen::Vector3d t = scene_centre - r * model_centre;
    cv::Matx44d m = cv::Matx44d::eye();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) m(i, j) = r(i, j);
      m(i, 3) = t[i];
    }
    cv::ppf_match_3d::Pose3DPtr pose(new cv::ppf_match_3d::Pose3D());
    pose->updatePose(m);
    seeds.push_back(pose);
  }
  cv::ppf_match_3d::ICP icp(options.iterations, options.tolerance, options.rejection_scale, options.levels);
  icp.registerModelToScene(src, dst, seeds);
  // The pose moves the model onto the scene: camera_from_object. Keep the best
  // by SeaMap's own measure (the ICP residual is in internal units).
  cv::Mat model_pc(static_cast<int>(model_structure.size()), 3, CV_32F);
  for (size_t k = 0; k < model_structure.size(); ++k)
    for (int i = 0; i < 3; ++i) model_pc.at<float>(static_cast<int>(k), i) = static_cast<float>(model_structure[k][i]);
  cv::flann::Index index(model_pc, cv::flann::KDTreeIndexParams(4));
  const auto score = [&](const cv::Matx44d& camera_from_object_cv) {
    Rigid camera_from_object = Rigid::Identity();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) camera_from_object.linear()(i, j) = camera_from_object_cv(i, j);
      camera_from_object.translation()[i] = camera_from_object_cv(i, 3);
    }
    IcpRegistration r;
    r.object_from_camera = camera_from_object.inverse();
    r.structure = static_cast<int>(scene_structure.size());
    double sum = 0;
    std::vector<float> query(3), d2(1);
    std::vector<int> idx(1);
    for (const Eigen::Vector3d& p : scene_structure) {
      const Eigen::Vector3f q = (r.object_from_camera * p).cast<float>();
      query = {q.x(), q.y(), q.z()};
      index.knnSearch(query, idx, d2, 1, cv::flann::SearchParams(32));
      if (d2[0] <= options.near_m * options.near_m) sum += d2[0], ++r.near;
    }
    r.rms_m = r.near ? std::sqrt(sum / r.near) : 1e9;
    return r;
  };
  size_t best = 0;
  for (size_t k = 0; k < seeds.size(); ++k) {
    const IcpRegistration r = score(seeds[k]->pose);
    if (k == 0 || r.near > out.near) out = r, best = k;
  }
  // From the structure's pose, the whole clouds: the seabed pins tilt and height.
  std::vector<cv::ppf_match_3d::Pose3DPtr> whole{seeds[best]};
  icp.registerModelToScene(WithNormals(model_all, options.normal_neighbours, Eigen::Vector3d::Zero()),
                           WithNormals(scene_all, options.normal_neighbours, Eigen::Vector3d::Zero()), whole);
  const IcpRegistration refined = score(whole[0]->pose);
  if (refined.near > out.near) out = refined;
  return out;
}

bool IcpFound(const IcpRegistration& registration, const IcpOptions& options, std::string* reason) {
  const bool found = registration.near >= options.min_near &&
                     registration.near >= options.min_near_fraction * registration.structure &&
                     registration.rms_m <= options.max_rms_m;
  if (!found && reason) {
    *reason = cv::format("ICP: %d of %d points off the seabed plane within %.0f mm of the model (need %d and %.0f %%)",
                         registration.near, registration.structure, 1000 * options.near_m, options.min_near,
                         100 * options.min_near_fraction);
    if (registration.near > 0) *reason += cv::format(", RMS %.1f mm", 1000 * registration.rms_m);
  }
  return found;
}

LocateResult LocateObjectIcp(const ObjectModel& model, const StereoCalibration& calibration,
                             const std::vector<LoadedPair>& pairs, const IcpOptions& options) {
  LocateResult result;
  result.method = "icp";
  std::vector<Eigen::Vector3d> model_points;
  for (const ModelPoint& p : model.points) model_points.push_back(p.xyz);
  for (const LoadedPair& p : pairs) {
    auto t0 = std::chrono::steady_clock::now();
    const StereoFrame frame = MakeStereoFrame(p.name, p.left, p.right, calibration, options.sift, options.match);
    PairResult pr;
    pr.pair = p.name;
    pr.features_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    t0 = std::chrono::steady_clock::now();
    std::vector<Eigen::Vector3d> scene;
    for (const StereoPoint& sp : frame.points) scene.push_back(sp.xyz);
    const IcpRegistration reg = RegisterIcp(model_points, scene, options);
    pr.registration_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    pr.object_from_camera = pr.single_object_from_camera = reg.object_from_camera;
    pr.stereo_points = static_cast<int>(scene.size());
    pr.inliers = reg.near;
    pr.matches = static_cast<int>(scene.size());
    pr.accepted = IcpFound(reg, options, &pr.reason);
    result.features_s += pr.features_s;
    result.registration_s += pr.registration_s;
    if (pr.accepted && !result.found) {
      result.found = true;
      result.object_from_camera = pr.object_from_camera;
      // Isotropic: the cloud's RMS over the points that agree, one independent
      // residual per normal neighbourhood (neighbouring residuals share a normal and a sampling offset).
      const double sigma = reg.rms_m / std::sqrt(std::max(1.0, reg.near / double(options.normal_neighbours)));
      result.position_sigma_m = Eigen::Vector3d::Constant(sigma);
      result.covariance.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * sigma * sigma;
      result.point_sigma_m = std::sqrt(3.0) * sigma;
    }
    result.pairs.push_back(pr);
  }
  if (!result.found)
    result.reason = "object not recognised by ICP: pair " + result.pairs[0].pair + ": " + result.pairs[0].reason;
  return result;
}

}  // namespace seamap
