#include "core/stereo/object_model.h"

#include <chrono>
#include <cstring>
#include <set>

#include "core/stereo/model_registration.h"
#include "core/stereo/stereo_bundle.h"
#include "core/util/error.h"
#include "core/util/json_file.h"

namespace seamap {
namespace {

const char* kB64 = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

std::string Base64(const uint8_t* data, size_t n) {
  std::string out;
  for (size_t i = 0; i < n; i += 3) {
    uint32_t v = data[i] << 16;
    if (i + 1 < n) v |= data[i + 1] << 8;
    if (i + 2 < n) v |= data[i + 2];
    out += kB64[(v >> 18) & 63];
    out += kB64[(v >> 12) & 63];
    out += i + 1 < n ? kB64[(v >> 6) & 63] : '=';
    out += i + 2 < n ? kB64[v & 63] : '=';
  }
  return out;
}

bool FromBase64(const std::string& text, std::vector<uint8_t>* out) {
  out->clear();
  uint32_t v = 0;
  int bits = 0;
  for (char c : text) {
    if (c == '=') break;
    const char* p = std::strchr(kB64, c);
    if (!p || !c) return false;
    v = (v << 6) | static_cast<uint32_t>(p - kB64);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out->push_back(static_cast<uint8_t>((v >> bits) & 0xFF));
    }
  }
  return true;
}

Eigen::Matrix3d Rotate(const Eigen::Matrix3d& r, const Eigen::Matrix3d& cov) {
  return r * cov * r.transpose();
}

}  // namespace

void ObjectModel::IndexDescriptors() {
  int rows = 0;
  for (const ModelPoint& p : points) rows += static_cast<int>(p.observations.size());
  descriptors.create(rows, 128, CV_8U);
  descriptor_point.clear();
  int row = 0;
  for (size_t k = 0; k < points.size(); ++k)
    for (const ModelObservation& o : points[k].observations) {
      o.descriptor.copyTo(descriptors.row(row++));
      descriptor_point.push_back(static_cast<int>(k));
    }
}

void ModelBuildOptions::Check() const {
  sift.Check();
  if (!(ratio > 0 && ratio <= 1)) throw InputError("", 0, "--ratio", "expected a number in (0, 1]");
}

ObjectModel BuildObjectModel(const std::vector<LoadedPair>& pairs, const StereoCalibration& calibration,
                             const std::string& name, const ModelBuildOptions& options, ModelBuildReport* report) {
  options.Check();
  const auto start = std::chrono::steady_clock::now();
  const RectifiedRig& rig = calibration.rig;
  ObjectModel model;
  model.name = name;
  model.fx_px = calibration.K1(0, 0);
  model.baseline_m = cv::norm(calibration.T);
  model.image_size = calibration.image_size;
  std::vector<StereoFrame> frames;
  for (const LoadedPair& p : pairs)
    frames.push_back(MakeStereoFrame(p.name, p.left, p.right, calibration, options.sift, options.match));

  // Per model point: (view, left keypoint) of each observation, for the bundle.
  std::vector<std::vector<std::pair<int, int>>> seen_by;
  std::vector<int> view_of_frame(frames.size(), -1);
  std::vector<Rigid> frame_pose(frames.size(), Rigid::Identity());
  const auto add_points = [&](int f, const Rigid& pose, const std::set<int>& skip_left) {
    const StereoFrame& frame = frames[f];
    for (const StereoPoint& sp : frame.points) {
      if (skip_left.count(sp.left)) continue;
      ModelPoint p;
      p.xyz = pose * sp.xyz;
      p.cov = Rotate(pose.linear(), sp.cov);
      p.observations.push_back({view_of_frame[f], frame.left.raw_px[sp.left], frame.left.descriptors.row(sp.left)});
      model.points.push_back(p);
      seen_by.push_back({{f, sp.left}});
    }
  };
  view_of_frame[0] = 0;
  model.views.push_back({frames[0].name, Rigid::Identity()});
  add_points(0, Rigid::Identity(), {});
  model.IndexDescriptors();
  if (report)
    report->lines.push_back(
        cv::format("%s: %zu points (defines the frame)", frames[0].name.c_str(), frames[0].points.size()));

  // Register the other pairs against what is built so far; a pair that
  // overlaps none yet is retried after the others (chaining).
  ModelRegistrationOptions reg_options;
  reg_options.ratio = options.ratio;
  reg_options.inlier_px = options.inlier_px;
  bool progress = true;
  std::vector<std::string> last_failure(frames.size());
  while (progress) {
    progress = false;
    for (size_t f = 1; f < frames.size(); ++f) {
      if (view_of_frame[f] >= 0) continue;
      const Registration reg = RegisterPair(model, frames[f], rig, reg_options);
      if (!reg.ok || static_cast<int>(reg.inliers.size()) < options.min_inliers) {
        last_failure[f] = reg.ok ? cv::format("%zu inliers", reg.inliers.size()) : reg.failure;
        continue;
      }
      view_of_frame[f] = static_cast<int>(model.views.size());
      frame_pose[f] = reg.object_from_camera;
      model.views.push_back({frames[f].name, reg.object_from_camera});
      std::set<int> used;
      for (int k : reg.inliers) {
        const ModelMatch& m = reg.matches[k];
        model.points[m.point].observations.push_back(
            {view_of_frame[f], frames[f].left.raw_px[m.left], frames[f].left.descriptors.row(m.left)});
        seen_by[m.point].push_back({static_cast<int>(f), m.left});
        used.insert(m.left);
      }
      add_points(static_cast<int>(f), reg.object_from_camera, used);
      model.IndexDescriptors();
      if (report)
        report->lines.push_back(cv::format("%s: %zu points, %zu model matches, %zu inliers, %.2f px",
                                           frames[f].name.c_str(), frames[f].points.size(), reg.matches.size(),
                                           reg.inliers.size(), reg.rms_px));
      progress = true;
    }
  }
  for (size_t f = 1; f < frames.size(); ++f)
    if (view_of_frame[f] < 0)
      throw InputError(pairs[f].name, 0, "--pairs",
                       "overview pair " + frames[f].name + " shares too little with the others to be tied in (" +
                           last_failure[f] + ")");

  if (options.bundle && frames.size() > 1) {
    // Bundle over the overview pairs: pair 1 fixed (the gauge), other poses and all points free.
    BundleProblem problem;
    problem.poses = frame_pose;
    problem.pose_fixed.assign(frames.size(), false);
    problem.pose_fixed[0] = true;
    double sigma = 0;
    for (const StereoFrame& fr : frames) sigma += fr.sigma_px / frames.size();
    problem.sigma_px = sigma;
    for (size_t k = 0; k < model.points.size(); ++k) {
      BundlePoint p;
      p.xyz = model.points[k].xyz;
      problem.points.push_back(p);
      for (const auto& [f, l] : seen_by[k]) {
        BundleObservation o;
        o.pose = f;
        o.point = static_cast<int>(k);
        o.left_px = frames[f].left.rect_px[l];
        const int sp = frames[f].point_of_left[l];
        o.has_right = sp >= 0;
        if (o.has_right) o.right_px = frames[f].right.rect_px[frames[f].points[sp].right];
        problem.observations.push_back(o);
      }
    }
    const BundleResult r = SolveBundle(&problem, rig);
    if (report) report->bundle_rms_px = r.rms_px;
    for (size_t f = 0; f < frames.size(); ++f) {
      frame_pose[f] = problem.poses[f];
      model.views[view_of_frame[f]].second = problem.poses[f];
    }
    // Points: the bundle's position; covariance from the stereo observations
    // (inverse-covariance fusion of each view's triangulation).
    for (size_t k = 0; k < model.points.size(); ++k) {
      model.points[k].xyz = problem.points[k].xyz;
      Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
      for (const auto& [f, l] : seen_by[k]) {
        const int sp = frames[f].point_of_left[l];
        if (sp >= 0) info += Rotate(frame_pose[f].linear(), frames[f].points[sp].cov).inverse();
      }
      if (info.determinant() > 0) model.points[k].cov = info.inverse();
    }
  }
  if (!report) return model;
  report->pairs = static_cast<int>(frames.size());
  report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return model;
}

nlohmann::json ModelToJson(const ObjectModel& model) {
  nlohmann::json views = nlohmann::json::array(), points = nlohmann::json::array();
  for (const auto& [name, pose] : model.views)
    views.push_back({{"pair", name}, {"object_from_camera", RigidToJson(pose)}});
  for (size_t k = 0; k < model.points.size(); ++k) {
    const ModelPoint& p = model.points[k];
    nlohmann::json obs = nlohmann::json::array();
    for (const ModelObservation& o : p.observations)
      obs.push_back(
          {{"view", o.view}, {"uv", {o.raw_px.x, o.raw_px.y}}, {"descriptor", Base64(o.descriptor.ptr(), 128)}});
    std::vector<double> cov(p.cov.data(), p.cov.data() + 9);
    points.push_back({{"id", k}, {"xyz", {p.xyz.x(), p.xyz.y(), p.xyz.z()}}, {"covariance", cov}, {"views", obs}});
  }
  return {{"format", "seamap-stereo-model"},
          {"version", 1},
          {"name", model.name},
          {"frame", model.frame},
          {"calibration",
           {{"fx_px", model.fx_px},
            {"baseline_m", model.baseline_m},
            {"image_size", {model.image_size.width, model.image_size.height}}}},
          {"views", views},
          {"points", points}};
}

ObjectModel ModelFromJson(const nlohmann::json& j, const std::string& path) {
  const auto fail = [&](const std::string& key, const std::string& why) { throw InputError(path, 0, key, why); };
  if (!j.is_object() || j.value("format", "") != "seamap-stereo-model")
    fail("format", "not a SeaMap stereo model (expected \"format\": \"seamap-stereo-model\")");
  if (j.value("version", 0) != 1) fail("version", "expected version 1");
  ObjectModel m;
  m.name = j.value("name", "");
  m.frame = j.value("frame", "first-overview-left-camera");
  try {
    const auto& c = j.at("calibration");
    m.fx_px = c.at("fx_px").get<double>();
    m.baseline_m = c.at("baseline_m").get<double>();
    m.image_size = {c.at("image_size").at(0).get<int>(), c.at("image_size").at(1).get<int>()};
  } catch (const nlohmann::json::exception&) {
    fail("calibration", "expected fx_px, baseline_m and image_size [w, h]");
  }
  if (!j.contains("views") || !j["views"].is_array() || j["views"].empty()) fail("views", "expected a list of views");
  for (size_t k = 0; k < j["views"].size(); ++k) {
    const auto& v = j["views"][k];
    const std::string key = "views[" + std::to_string(k) + "]";
    if (!v.is_object() || !v.contains("pair") || !v["pair"].is_string()) fail(key + ".pair", "expected a pair name");
    m.views.push_back({v["pair"].get<std::string>(), RigidFromJson(v.value("object_from_camera", nlohmann::json()),
                                                                   path, key + ".object_from_camera")});
  }
  if (!j.contains("points") || !j["points"].is_array()) fail("points", "expected a list of points");
  std::vector<uint8_t> bytes;
  for (size_t k = 0; k < j["points"].size(); ++k) {
    const auto& p = j["points"][k];
    const std::string key = "points[" + std::to_string(k) + "]";
    ModelPoint mp;
    try {
      for (int i = 0; i < 3; ++i) mp.xyz[i] = p.at("xyz").at(i).get<double>();
      for (int i = 0; i < 9; ++i) mp.cov.data()[i] = p.at("covariance").at(i).get<double>();
    } catch (const nlohmann::json::exception&) {
      fail(key, "expected xyz (3 numbers) and covariance (9 numbers)");
    }
    if (!(mp.cov.determinant() > 0)) fail(key + ".covariance", "not positive definite");
    if (!p.contains("views") || !p["views"].is_array() || p["views"].empty())
      fail(key + ".views", "expected the views that saw the point");
    for (const auto& o : p["views"]) {
      ModelObservation obs;
      try {
        obs.view = o.at("view").get<int>();
        obs.raw_px = {o.at("uv").at(0).get<double>(), o.at("uv").at(1).get<double>()};
        if (!FromBase64(o.at("descriptor").get<std::string>(), &bytes) || bytes.size() != 128) throw 0;
      } catch (...) {
        fail(key + ".views", "expected view, uv [u, v] and a base64 descriptor of 128 bytes");
      }
      if (obs.view < 0 || obs.view >= static_cast<int>(m.views.size())) fail(key + ".views", "view out of range");
      obs.descriptor = cv::Mat(1, 128, CV_8U, bytes.data()).clone();
      mp.observations.push_back(obs);
    }
    m.points.push_back(mp);
  }
  if (m.points.size() < 6) fail("points", "a model needs at least 6 points");
  m.IndexDescriptors();
  return m;
}

ObjectModel LoadObjectModel(const std::string& path) {
  return ModelFromJson(ReadJsonFile(path, "model (--model)"), path);
}

}  // namespace seamap
