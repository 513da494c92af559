#include "core/stereo/icp_baseline.h"

#include <chrono>
#include <cmath>

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

IcpRegistration RegisterIcp(const std::vector<Eigen::Vector3d>& model_object,
                            const std::vector<Eigen::Vector3d>& scene_camera, const IcpOptions& options) {
  IcpRegistration out;
  if (model_object.size() < 10 || scene_camera.size() < 10) return out;
  // Model normals towards the first overview camera (the frame's origin), scene normals towards the camera.
  const cv::Mat src = WithNormals(model_object, options.normal_neighbours, Eigen::Vector3d::Zero());
  const cv::Mat dst = WithNormals(scene_camera, options.normal_neighbours, Eigen::Vector3d::Zero());
  Eigen::Vector3d model_centre = Eigen::Vector3d::Zero(), scene_centre = Eigen::Vector3d::Zero();
  for (const auto& p : model_object) model_centre += p / model_object.size();
  for (const auto& p : scene_camera) scene_centre += p / scene_camera.size();
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
  cv::Mat model_pc(static_cast<int>(model_object.size()), 3, CV_32F);
  for (size_t k = 0; k < model_object.size(); ++k)
    for (int i = 0; i < 3; ++i) model_pc.at<float>(static_cast<int>(k), i) = static_cast<float>(model_object[k][i]);
  cv::flann::Index index(model_pc, cv::flann::KDTreeIndexParams(4));
  bool first = true;
  for (const auto& seed : seeds) {
    Rigid camera_from_object = Rigid::Identity();
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) camera_from_object.linear()(i, j) = seed->pose(i, j);
      camera_from_object.translation()[i] = seed->pose(i, 3);
    }
    const Rigid object_from_camera = camera_from_object.inverse();
    double sum = 0;
    int near = 0;
    for (const Eigen::Vector3d& p : scene_camera) {
      const Eigen::Vector3f q = (object_from_camera * p).cast<float>();
      std::vector<float> query{q.x(), q.y(), q.z()};
      std::vector<int> idx(1);
      std::vector<float> d2(1);
      index.knnSearch(query, idx, d2, 1, cv::flann::SearchParams(32));
      if (d2[0] <= options.near_m * options.near_m) sum += d2[0], ++near;
    }
    if (first || near > out.near) {
      first = false;
      out.object_from_camera = object_from_camera;
      out.near = near;
      out.rms_m = near ? std::sqrt(sum / near) : 1e9;
    }
  }
  return out;
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
    pr.accepted = reg.near >= options.min_near && reg.rms_m <= options.max_rms_m;
    if (!pr.accepted)
      pr.reason = cv::format("ICP: %d points within %.0f mm (need %d), RMS %.1f mm", reg.near, 1000 * options.near_m,
                             options.min_near, 1000 * reg.rms_m);
    result.features_s += pr.features_s;
    result.registration_s += pr.registration_s;
    if (pr.accepted && !result.found) {
      result.found = true;
      result.object_from_camera = pr.object_from_camera;
      // Isotropic: the cloud's RMS over the points that agree.
      const double sigma = reg.rms_m / std::sqrt(std::max(1, reg.near));
      result.position_sigma_m = Eigen::Vector3d::Constant(sigma);
      result.covariance.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * sigma * sigma;
    }
    result.pairs.push_back(pr);
  }
  if (!result.found)
    result.reason = "object not recognised by ICP: pair " + result.pairs[0].pair + ": " + result.pairs[0].reason;
  return result;
}

}  // namespace seamap
