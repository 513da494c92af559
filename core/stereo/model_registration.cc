#include "core/stereo/model_registration.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include <opencv2/calib3d.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/flann.hpp>

namespace seamap {

std::vector<ModelMatch> MatchToModel(const ObjectModel& model, const ImageFeatures& left, double ratio) {
  std::vector<ModelMatch> out;
  if (model.descriptors.empty() || left.descriptors.empty()) return out;
  cv::Mat train, query;
  model.descriptors.convertTo(train, CV_32F);
  left.descriptors.convertTo(query, CV_32F);
  cv::FlannBasedMatcher matcher(cv::makePtr<cv::flann::KDTreeIndexParams>(4), cv::makePtr<cv::flann::SearchParams>(64));
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(query, train, knn, 6);
  std::map<int, ModelMatch> best_of_point;
  for (const auto& candidates : knn) {
    if (candidates.empty()) continue;
    const int point = model.descriptor_point[candidates[0].trainIdx];
    // The second-best of another point: the same point seen in several views is no ambiguity.
    float second = -1;
    for (size_t k = 1; k < candidates.size(); ++k)
      if (model.descriptor_point[candidates[k].trainIdx] != point) {
        second = candidates[k].distance;
        break;
      }
    if (second >= 0 && candidates[0].distance >= ratio * second) continue;
    const ModelMatch m{point, candidates[0].queryIdx, candidates[0].distance};
    auto it = best_of_point.find(point);
    if (it == best_of_point.end() || it->second.distance > m.distance) best_of_point[point] = m;
  }
  for (const auto& [point, m] : best_of_point) out.push_back(m);
  return out;
}

double MatchError(const ObjectModel& model, const StereoFrame& frame, const RectifiedRig& rig, const ModelMatch& m,
                  const Rigid& object_from_camera) {
  cv::Point2d l, r;
  if (!ProjectToPair(rig, object_from_camera, model.points[m.point].xyz, &l, &r)) return 1e9;
  double e = cv::norm(l - frame.left.rect_px[m.left]);
  const int sp = frame.point_of_left[m.left];
  if (sp >= 0) e = std::max(e, cv::norm(r - frame.right.rect_px[frame.points[sp].right]));
  return e;
}

namespace {

std::vector<int> Inliers(const ObjectModel& model, const StereoFrame& frame, const RectifiedRig& rig,
                         const std::vector<ModelMatch>& matches, const Rigid& pose, double threshold_px) {
  std::vector<int> in;
  for (size_t k = 0; k < matches.size(); ++k)
    if (MatchError(model, frame, rig, matches[k], pose) <= threshold_px) in.push_back(static_cast<int>(k));
  return in;
}

// Bundle over one pair: the pose free, the inlier model points free under their priors.
double Refine(const ObjectModel& model, const StereoFrame& frame, const RectifiedRig& rig,
              const std::vector<ModelMatch>& matches, const std::vector<int>& inliers, Rigid* pose) {
  BundleProblem problem;
  problem.poses = {*pose};
  problem.pose_fixed = {false};
  problem.sigma_px = frame.sigma_px;
  for (int k : inliers) {
    const ModelMatch& m = matches[k];
    BundlePoint p;
    p.xyz = p.prior_xyz = model.points[m.point].xyz;
    p.prior_cov = model.points[m.point].cov;
    p.has_prior = true;
    BundleObservation o;
    o.pose = 0;
    o.point = static_cast<int>(problem.points.size());
    o.left_px = frame.left.rect_px[m.left];
    const int sp = frame.point_of_left[m.left];
    o.has_right = sp >= 0;
    if (o.has_right) o.right_px = frame.right.rect_px[frame.points[sp].right];
    problem.points.push_back(p);
    problem.observations.push_back(o);
  }
  const BundleResult r = SolveBundle(&problem, rig);
  *pose = problem.poses[0];
  return r.rms_px;
}

}  // namespace

Registration RegisterPair(const ObjectModel& model, const StereoFrame& frame, const RectifiedRig& rig,
                          const ModelRegistrationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  Registration reg;
  reg.matches = MatchToModel(model, frame.left, options.ratio);
  std::vector<int> with_3d;
  for (size_t k = 0; k < reg.matches.size(); ++k)
    if (frame.point_of_left[reg.matches[k].left] >= 0) with_3d.push_back(static_cast<int>(k));
  reg.matches_3d = static_cast<int>(with_3d.size());
  const auto finish = [&]() {
    reg.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return reg;
  };
  if (reg.matches.size() < 4) {
    reg.failure = cv::format("%zu model matches (need at least 4)", reg.matches.size());
    return finish();
  }

  Rigid best_pose = Rigid::Identity();
  size_t best_count = 0;
  std::mt19937_64 rng(options.seed);
  if (with_3d.size() >= 6) {
    std::uniform_int_distribution<size_t> pick(0, with_3d.size() - 1);
    int iterations = options.ransac_iterations;
    for (int it = 0; it < iterations; ++it) {
      const size_t a = pick(rng), b = pick(rng), c = pick(rng);
      if (a == b || b == c || a == c) continue;
      std::vector<Eigen::Vector3d> src, dst;
      for (size_t s : {a, b, c}) {
        const ModelMatch& m = reg.matches[with_3d[s]];
        src.push_back(frame.points[frame.point_of_left[m.left]].xyz);
        dst.push_back(model.points[m.point].xyz);
      }
      // Degenerate (nearly collinear or tiny) samples give wild hypotheses.
      if (((src[1] - src[0]).cross(src[2] - src[0])).norm() < 1e-3) continue;
      const Rigid hypothesis = FitRigid(src, dst);  // object_from_camera
      const std::vector<int> in = Inliers(model, frame, rig, reg.matches, hypothesis, options.inlier_px);
      if (in.size() > best_count) {
        best_count = in.size();
        best_pose = hypothesis;
        const double w = static_cast<double>(in.size()) / reg.matches.size();
        const double needed = std::log(0.001) / std::log(std::max(1e-9, 1 - w * w * w));
        iterations = std::min(iterations, std::max(50, static_cast<int>(std::ceil(needed))));
      }
    }
  } else {
    // Too few stereo partners: PnP in the rectified left camera.
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (const ModelMatch& m : reg.matches) {
      const Eigen::Vector3d& p = model.points[m.point].xyz;
      object.emplace_back(p.x(), p.y(), p.z());
      image.push_back(frame.left.rect_px[m.left]);
    }
    const cv::Matx33d k(rig.f, 0, rig.cx, 0, rig.f, rig.cy, 0, 0, 1);
    cv::Mat rvec, tvec;
    if (cv::solvePnPRansac(object, image, k, cv::noArray(), rvec, tvec, false, 2000,
                           static_cast<float>(options.inlier_px), 0.999, cv::noArray(), cv::SOLVEPNP_SQPNP)) {
      cv::Mat rm;
      cv::Rodrigues(rvec, rm);
      Rigid rect_from_object = Rigid::Identity();
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) rect_from_object.linear()(r, c) = rm.at<double>(r, c);
        rect_from_object.translation()[r] = tvec.at<double>(r);
      }
      Rigid left_from_rect = Rigid::Identity();
      left_from_rect.linear() = rig.rect_from_left.transpose();
      best_pose = (left_from_rect * rect_from_object).inverse();
      best_count = Inliers(model, frame, rig, reg.matches, best_pose, options.inlier_px).size();
    }
  }
  if (best_count < 4) {
    reg.failure = cv::format("no consistent pose (%zu of %zu matches agree)", best_count, reg.matches.size());
    return finish();
  }
  // Refine, re-select the inliers with the refined pose, refine once more.
  reg.object_from_camera = best_pose;
  reg.inliers = Inliers(model, frame, rig, reg.matches, reg.object_from_camera, options.inlier_px);
  for (int round = 0; round < 2; ++round) {
    reg.rms_px = Refine(model, frame, rig, reg.matches, reg.inliers, &reg.object_from_camera);
    reg.inliers = Inliers(model, frame, rig, reg.matches, reg.object_from_camera, options.inlier_px);
  }
  std::set<int> views;
  for (int k : reg.inliers)
    for (const ModelObservation& o : model.points[reg.matches[k].point].observations) views.insert(o.view);
  reg.model_views_matched = static_cast<int>(views.size());
  reg.ok = reg.inliers.size() >= 4;
  if (!reg.ok) reg.failure = cv::format("%zu inliers after refinement", reg.inliers.size());
  return finish();
}

}  // namespace seamap
