#include "core/stereo/object_locator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "core/stereo/stereo_bundle.h"
#include "core/util/error.h"
#include "core/util/json_file.h"

namespace seamap {
namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

struct UnionFind {
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int Find(int a) { return parent[a] == a ? a : parent[a] = Find(parent[a]); }
  void Join(int a, int b) { parent[Find(a)] = Find(b); }
  std::vector<int> parent;
};

// Ratio-test matches between the stereo points of two pairs (left descriptors), mutual best.
std::vector<std::pair<int, int>> MatchStereoPoints(const StereoFrame& a, const StereoFrame& b, double ratio) {
  cv::Mat da(static_cast<int>(a.points.size()), 128, CV_8U), db(static_cast<int>(b.points.size()), 128, CV_8U);
  for (size_t k = 0; k < a.points.size(); ++k) a.left.descriptors.row(a.points[k].left).copyTo(da.row(k));
  for (size_t k = 0; k < b.points.size(); ++k) b.left.descriptors.row(b.points[k].left).copyTo(db.row(k));
  std::vector<std::pair<int, int>> out;
  if (da.rows < 2 || db.rows < 2) return out;
  cv::Mat fa, fb;
  da.convertTo(fa, CV_32F);
  db.convertTo(fb, CV_32F);
  cv::FlannBasedMatcher matcher(cv::makePtr<cv::flann::KDTreeIndexParams>(4), cv::makePtr<cv::flann::SearchParams>(64));
  std::vector<std::vector<cv::DMatch>> ab, ba;
  matcher.knnMatch(fa, fb, ab, 2);
  matcher.knnMatch(fb, fa, ba, 2);
  for (const auto& m : ab) {
    if (m.size() < 2 || m[0].distance >= ratio * m[1].distance) continue;
    const auto& back = ba[m[0].trainIdx];
    if (back.empty() || back[0].trainIdx != m[0].queryIdx) continue;
    out.emplace_back(m[0].queryIdx, m[0].trainIdx);
  }
  return out;
}

}  // namespace

RigMotion ReadRigMotion(const std::string& path) {
  nlohmann::json j = ReadJsonFile(path, "rig's motion file (--motion)");
  RigMotion motion;
  if (!j.is_object() || !j.contains("world_from_camera") || !j["world_from_camera"].is_object())
    throw InputError(path, 0, "world_from_camera", "expected an object of 4x4 poses by pair name");
  for (const auto& [pair, pose] : j["world_from_camera"].items())
    motion.world_from_camera[pair] =
        RigidFromJson(pose, path, "world_from_camera." + (pair.size() > 80 ? pair.substr(0, 80) + "..." : pair));
  const auto positive = [&](const char* key, double most, double* value) {
    if (!j.contains(key)) return;
    if (!j[key].is_number() || !(j[key].get<double>() > 0 && j[key].get<double>() <= most))
      throw InputError(path, 0, key, "expected a positive number, at most " + std::to_string(static_cast<int>(most)));
    *value = j[key].get<double>();
  };
  positive("sigma_m", 1000, &motion.sigma_m);
  positive("sigma_deg", 180, &motion.sigma_deg);
  return motion;
}

void LocateOptions::Check() const {
  sift.Check();
  if (min_inliers < 4) throw InputError("", 0, "--min-inliers", "expected at least 4");
  if (min_tie_points < 0) throw InputError("", 0, "--min-tie-points", "expected 0 or more");
  if (!(registration.ratio > 0 && registration.ratio <= 1)) throw InputError("", 0, "--ratio", "expected (0, 1]");
}

std::string JudgePair(const Registration& reg, const StereoFrame& frame, const ObjectModel& model, cv::Size image_size,
                      const LocateOptions& options, bool* spread_only) {
  if (spread_only) *spread_only = false;
  if (!reg.ok) return reg.failure;
  const int inliers = static_cast<int>(reg.inliers.size());
  if (inliers < options.min_inliers)
    return cv::format("%d inliers of %zu model matches (need %d)", inliers, reg.matches.size(), options.min_inliers);
  if (inliers < options.min_inlier_share * reg.matches.size())
    return cv::format("only %d of %zu model matches agree (need %.0f %%)", inliers, reg.matches.size(),
                      100 * options.min_inlier_share);
  if (reg.rms_px > options.max_rms_px)
    return cv::format("reprojection RMS %.2f px (limit %.2f px)", reg.rms_px, options.max_rms_px);
  std::vector<cv::Point2f> px;
  Eigen::MatrixXd cloud(inliers, 3);
  for (int k = 0; k < inliers; ++k) {
    const ModelMatch& m = reg.matches[reg.inliers[k]];
    px.push_back(frame.left.rect_px[m.left]);
    cloud.row(k) = model.points[m.point].xyz.transpose();
  }
  std::vector<cv::Point2f> hull;
  cv::convexHull(px, hull);
  const double hull_share = cv::contourArea(hull) / image_size.area();
  if (spread_only) *spread_only = true;
  if (hull_share < options.min_hull_share)
    return cv::format("inliers cover %.2f %% of the image (need %.0f %%)", 100 * hull_share,
                      100 * options.min_hull_share);
  const Eigen::MatrixXd centred = cloud.rowwise() - cloud.colwise().mean();
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::MatrixXd>(centred).singularValues() / std::sqrt(inliers);
  if (sv[1] < options.min_spread_m)
    return cv::format("inliers lie on a line (spread %.3f m, need %.2f m)", sv[1], options.min_spread_m);
  if (spread_only) *spread_only = false;
  return "";
}

LocateResult LocateObject(const ObjectModel& model, const StereoCalibration& calibration,
                          const std::vector<LoadedPair>& pairs, const LocateOptions& options) {
  options.Check();
  const RectifiedRig& rig = calibration.rig;
  LocateResult result;
  std::vector<StereoFrame> frames;
  std::vector<Registration> regs;
  std::vector<int> accepted, spread_only;
  for (const LoadedPair& p : pairs) {
    auto t0 = std::chrono::steady_clock::now();
    frames.push_back(MakeStereoFrame(p.name, p.left, p.right, calibration, options.sift, options.match));
    PairResult pr;
    pr.pair = p.name;
    pr.features_s = Seconds(t0);
    t0 = std::chrono::steady_clock::now();
    regs.push_back(RegisterPair(model, frames.back(), rig, options.registration));
    const Registration& reg = regs.back();
    pr.registration_s = Seconds(t0);
    bool only_spread = false;
    pr.reason = JudgePair(reg, frames.back(), model, calibration.image_size, options, &only_spread);
    pr.accepted = pr.reason.empty();
    pr.single_object_from_camera = pr.object_from_camera = reg.object_from_camera;
    pr.matches = static_cast<int>(reg.matches.size());
    pr.inliers = static_cast<int>(reg.inliers.size());
    pr.model_views_matched = reg.model_views_matched;
    pr.reprojection_rms_px = reg.rms_px;
    pr.stereo_points = static_cast<int>(frames.back().points.size());
    result.features_s += pr.features_s;
    result.registration_s += pr.registration_s;
    if (pr.accepted) accepted.push_back(static_cast<int>(result.pairs.size()));
    if (only_spread) spread_only.push_back(static_cast<int>(result.pairs.size()));
    result.pairs.push_back(pr);
  }
  if (accepted.empty()) {
    result.reason = "object not recognised: pair " + result.pairs[0].pair + ": " + result.pairs[0].reason;
    return result;
  }
  // A pair whose inliers are good but cover a small patch (the object half out of view) cannot be
  // trusted alone, but constrains the joint solution of accepted pairs, which is judged as a whole
  // (agreement of every pair, joint RMS, position sigma).
  for (int f : spread_only) {
    result.pairs[f].accepted = result.pairs[f].joined = true;
    accepted.push_back(f);
  }
  std::sort(accepted.begin(), accepted.end());

  const auto t_joint = std::chrono::steady_clock::now();
  // Each round either ends or drops at least one pair.
  for (size_t round = 0; round <= pairs.size(); ++round) {
    // One pose per accepted pair; matched model points under their priors; tie points free.
    BundleProblem problem;
    double sigma = 0;
    std::map<int, int> bundle_of_model_point;
    std::vector<std::map<int, int>> point_of_left(accepted.size());  // per pose: left keypoint -> bundle point
    for (size_t a = 0; a < accepted.size(); ++a) {
      const int f = accepted[a];
      problem.poses.push_back(result.pairs[f].single_object_from_camera);
      problem.pose_fixed.push_back(false);
      sigma += frames[f].sigma_px / accepted.size();
      for (int k : regs[f].inliers) {
        const ModelMatch& m = regs[f].matches[k];
        auto [it, added] = bundle_of_model_point.emplace(m.point, static_cast<int>(problem.points.size()));
        if (added) {
          BundlePoint p;
          p.xyz = p.prior_xyz = model.points[m.point].xyz;
          p.prior_cov = model.points[m.point].cov;
          p.has_prior = true;
          problem.points.push_back(p);
        }
        point_of_left[a][m.left] = it->second;
      }
    }
    problem.sigma_px = sigma;
    // The vehicle's measure of the rig's motion ties each later pair to the first.
    std::vector<bool> moved_with_first(accepted.size(), false);
    const auto first_pose = options.motion.world_from_camera.find(result.pairs[accepted[0]].pair);
    for (size_t a = 1; a < accepted.size() && first_pose != options.motion.world_from_camera.end(); ++a) {
      const auto pose = options.motion.world_from_camera.find(result.pairs[accepted[a]].pair);
      if (pose == options.motion.world_from_camera.end()) continue;
      BundleMotion m;
      m.from_pose = 0;
      m.to_pose = static_cast<int>(a);
      m.from_camera_from_to_camera = first_pose->second.inverse() * pose->second;
      // Two poses, each off by sigma: their relative pose by sqrt(2) sigma.
      m.sigma_m = std::sqrt(2.0) * options.motion.sigma_m;
      m.sigma_rad = std::sqrt(2.0) * options.motion.sigma_deg * M_PI / 180;
      problem.motions.push_back(m);
      moved_with_first[a] = true;
    }
    int tie_points = 0;
    std::vector<std::pair<size_t, int>> weak;  // (accepted index, its tie points), ascending
    if (options.tie_points && accepted.size() > 1) {
      // Nodes: (pose a, stereo point s); edges: verified matches between pairs.
      std::vector<int> offset(accepted.size() + 1, 0);
      for (size_t a = 0; a < accepted.size(); ++a)
        offset[a + 1] = offset[a] + static_cast<int>(frames[accepted[a]].points.size());
      UnionFind sets(offset.back());
      for (size_t a = 0; a < accepted.size(); ++a)
        for (size_t b = a + 1; b < accepted.size(); ++b) {
          const StereoFrame &fa = frames[accepted[a]], &fb = frames[accepted[b]];
          for (const auto& [sa, sb] : MatchStereoPoints(fa, fb, options.registration.ratio)) {
            const Eigen::Vector3d p = problem.poses[a] * fa.points[sa].xyz;
            cv::Point2d l, r;
            if (!ProjectToPair(rig, problem.poses[b], p, &l, &r)) continue;
            if (cv::norm(l - fb.left.rect_px[fb.points[sb].left]) > 3 ||
                cv::norm(r - fb.right.rect_px[fb.points[sb].right]) > 3)
              continue;
            sets.Join(offset[a] + sa, offset[b] + sb);
          }
        }
      std::map<int, std::vector<std::pair<int, int>>> groups;  // root -> (pose, stereo point)
      for (size_t a = 0; a < accepted.size(); ++a)
        for (int s = 0; s < static_cast<int>(frames[accepted[a]].points.size()); ++s) {
          const int node = offset[a] + s;
          groups[sets.Find(node)].push_back({static_cast<int>(a), s});
        }
      std::vector<int> ties_of(accepted.size(), 0);
      for (auto& [root, nodes] : groups) {
        if (nodes.size() < 2) continue;
        std::vector<int> poses_seen(accepted.size(), 0);
        int model_point = -1;
        bool conflict = false;
        for (const auto& [a, s] : nodes) {
          if (++poses_seen[a] > 1) conflict = true;
          auto it = point_of_left[a].find(frames[accepted[a]].points[s].left);
          if (it != point_of_left[a].end()) {
            if (model_point >= 0 && model_point != it->second) conflict = true;
            model_point = it->second;
          }
        }
        if (conflict) continue;
        int target = model_point;
        if (target < 0) {
          for (const auto& [a, s] : nodes) ++ties_of[a];
          BundlePoint p;
          p.xyz.setZero();
          for (const auto& [a, s] : nodes) p.xyz += problem.poses[a] * frames[accepted[a]].points[s].xyz;
          p.xyz /= static_cast<double>(nodes.size());
          target = static_cast<int>(problem.points.size());
          problem.points.push_back(p);
          ++tie_points;
        }
        for (const auto& [a, s] : nodes) point_of_left[a].emplace(frames[accepted[a]].points[s].left, target);
      }
      for (size_t a = 1; a < accepted.size(); ++a)
        if (ties_of[a] < options.min_tie_points && !moved_with_first[a]) weak.push_back({a, ties_of[a]});
    }
    // A pair tied to the others by a handful of points adds its own error to the
    // first pair's pose more than it averages it out (seen in murky water, 2-10
    // tie points): it stays out. The first pair used always stays.
    if (!weak.empty()) {
      for (auto it = weak.rbegin(); it != weak.rend(); ++it) {
        PairResult& dropped = result.pairs[accepted[it->first]];
        dropped.accepted = false;
        dropped.reason =
            cv::format("only %d points tie it to the other pairs (need %d)", it->second, options.min_tie_points);
        accepted.erase(accepted.begin() + it->first);
      }
      continue;
    }
    for (size_t a = 0; a < accepted.size(); ++a) {
      const StereoFrame& fr = frames[accepted[a]];
      for (const auto& [left, point] : point_of_left[a]) {
        BundleObservation o;
        o.pose = static_cast<int>(a);
        o.point = point;
        o.left_px = fr.left.rect_px[left];
        const int sp = fr.point_of_left[left];
        o.has_right = sp >= 0;
        if (o.has_right) o.right_px = fr.right.rect_px[fr.points[sp].right];
        problem.observations.push_back(o);
      }
    }
    const BundleResult solved = SolveBundle(&problem, rig, 0);
    result.tie_points = tie_points;
    result.joint_rms_px = solved.rms_px;
    result.covariance = solved.covariance;
    for (int i = 0; i < 3; ++i) {
      result.rotation_sigma_deg[i] = std::sqrt(std::max(0.0, solved.covariance(i, i))) * 180 / M_PI;
      result.position_sigma_m[i] = std::sqrt(std::max(0.0, solved.covariance(i + 3, i + 3)));
    }
    for (size_t a = 0; a < accepted.size(); ++a) result.pairs[accepted[a]].object_from_camera = problem.poses[a];
    result.object_from_camera = problem.poses[0];
    if (!solved.has_covariance) {
      result.reason = "the joint problem is rank deficient (no covariance)";
      result.found = false;
      break;
    }
    // Each pair's own pose must agree with the joint one; drop the worst that does not.
    const double sigma_pos = result.position_sigma_m.norm(), sigma_rot = result.rotation_sigma_deg.norm();
    int worst = -1;
    double worst_score = 1;
    for (size_t a = 0; a < accepted.size(); ++a) {
      const PairResult& pr = result.pairs[accepted[a]];
      const Rigid delta = pr.single_object_from_camera.inverse() * pr.object_from_camera;
      const double score = std::max(RotationAngleDeg(delta.linear()) / std::max(0.5, 5 * sigma_rot),
                                    delta.translation().norm() / std::max(0.01, 5 * sigma_pos));
      if (score > worst_score) worst_score = score, worst = static_cast<int>(a);
    }
    if (worst < 0 || accepted.size() == 1) {
      result.found = true;
      break;
    }
    PairResult& dropped = result.pairs[accepted[worst]];
    dropped.accepted = false;
    dropped.reason = "its own pose disagrees with the joint solution of the other pairs";
    accepted.erase(accepted.begin() + worst);
  }
  if (result.found) {  // the solution's covariance carried to the model's points
    std::vector<Eigen::Vector3d> model_xyz;
    for (const ModelPoint& p : model.points) model_xyz.push_back(p.xyz);
    result.point_sigma_m = PointSigmaM(result.object_from_camera, result.covariance, model_xyz);
  }
  result.joint_s = Seconds(t_joint);
  if (result.found && result.joint_rms_px > options.max_rms_px) {
    result.found = false;
    result.reason =
        cv::format("joint reprojection RMS %.2f px (limit %.2f px)", result.joint_rms_px, options.max_rms_px);
  }
  if (result.found && result.point_sigma_m > options.max_point_sigma_m) {
    result.found = false;
    result.reason = cv::format("the object's points are uncertain by %.3f m (limit %.3f m)", result.point_sigma_m,
                               options.max_point_sigma_m);
  }
  return result;
}

nlohmann::json LocateResultToJson(const LocateResult& r, const std::string& model_name) {
  nlohmann::json views = nlohmann::json::array(), rejected = nlohmann::json::array();
  for (const PairResult& p : r.pairs) {
    nlohmann::json v = {{"pair", p.pair},
                        {"inliers", p.inliers},
                        {"matches", p.matches},
                        {"stereo_points", p.stereo_points},
                        {"reprojection_rms_px", p.reprojection_rms_px},
                        {"model_views_matched", p.model_views_matched},
                        {"time_s", p.features_s + p.registration_s},
                        {"features_s", p.features_s},
                        {"registration_s", p.registration_s}};
    if (p.accepted) {
      v["object_from_camera"] = RigidToJson(p.object_from_camera);
      v["single_pair_object_from_camera"] = RigidToJson(p.single_object_from_camera);
      if (p.joined) v["joined_despite"] = p.reason;
      views.push_back(v);
    } else {
      v["reason"] = p.reason;
      rejected.push_back(v);
    }
  }
  nlohmann::json j = {
      {"format", "seamap-stereo-pose"},
      {"version", 1},
      {"found", r.found},
      {"model", model_name},
      {"method", r.method},
      {"views", views},
      {"rejected", rejected},
      {"tie_points", r.tie_points},
      {"joint_rms_px", r.joint_rms_px},
      {"timing", {{"features_s", r.features_s}, {"registration_s", r.registration_s}, {"joint_s", r.joint_s}}}};
  if (!r.found) j["reason"] = r.reason;
  if (r.found) {
    j["object_from_camera"] = RigidToJson(r.object_from_camera);
    const Eigen::Vector3d c = r.object_from_camera.translation();
    j["camera_in_object_m"] = {c.x(), c.y(), c.z()};
    nlohmann::json cov = nlohmann::json::array();
    for (int i = 0; i < 6; ++i) {
      nlohmann::json row = nlohmann::json::array();
      for (int k = 0; k < 6; ++k) row.push_back(r.covariance(i, k));
      cov.push_back(row);
    }
    j["uncertainty"] = {
        {"covariance_6x6", cov},
        {"position_sigma_m", {r.position_sigma_m.x(), r.position_sigma_m.y(), r.position_sigma_m.z()}},
        {"rotation_sigma_deg", {r.rotation_sigma_deg.x(), r.rotation_sigma_deg.y(), r.rotation_sigma_deg.z()}},
        {"point_sigma_m", r.point_sigma_m}};
  } else {
    j["object_from_camera"] = nullptr;
  }
  return j;
}

}  // namespace seamap
