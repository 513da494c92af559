#include "core/sim/stereo_survey.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/geo/local_frame.h"
#include "core/util/error.h"

namespace seamap {
namespace fs = std::filesystem;
namespace {

// A camera looking straight down from (x, y, z) with its x axis at `heading` (rad, from scene x towards y).
Rigid DownLookingCamera(double x, double y, double z, double heading) {
  Rigid t = Rigid::Identity();
  const double c = std::cos(heading), s = std::sin(heading);
  Eigen::Matrix3d r;
  r.col(0) = Eigen::Vector3d(c, s, 0);   // image right
  r.col(1) = Eigen::Vector3d(s, -c, 0);  // image down
  r.col(2) = Eigen::Vector3d(0, 0, -1);  // optical axis, down
  t.linear() = r;
  t.translation() = Eigen::Vector3d(x, y, z);
  return t;
}

void WritePair(const StereoImages& images, const fs::path& dir, const std::string& name) {
  fs::create_directories(dir);
  for (const auto& [side, image] : {std::pair{"left", images.left}, std::pair{"right", images.right}}) {
    const fs::path path = dir / (name + "_" + side + ".png");
    if (!cv::imwrite(path.string(), image)) throw InputError(path.string(), 0, "", "cannot write the image");
  }
}

// The scene's frame on the Earth: x east, y north, z up from the seabed at dive_seabed_depth_m.
// The vehicle's navigation point is the left camera (its rig looks down, image top to the bow).
void SimulateDive(const StereoSurveyOptions& o, const StereoScene& scene, const StereoCalibration& rig,
                  const StereoSurveySummary& summary, const fs::path& out, uint64_t* noise_seed) {
  std::mt19937_64 rng(o.seed * 15485863 + 11);
  const auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  const LocalFrame earth(LatLon{o.dive_origin_lat, o.dive_origin_lon});
  const double top = scene.top_z_m;
  struct Leg {
    double time_s, x, y, z, heading;  // mid-leg: the pair's pose (left camera), heading from x towards y
  };
  // The compass heading of a down-looking camera's bow (image top, -y) and the body on the Earth.
  const auto compass = [](double heading) { return std::fmod(-heading * 180 / M_PI + 720, 360.0); };
  std::vector<Leg> legs;
  double t = 20;
  for (int k = 0; k <= o.dive_sightings; ++k) {  // the last one: after the navigation ends
    const double angle = uniform(0, 2 * M_PI), offset = uniform(0, 0.8);
    // Whole milliseconds: the pair's name holds its time exactly.
    legs.push_back({std::round((t + uniform(0, 5)) * 1000) / 1000, offset * std::cos(angle), offset * std::sin(angle),
                    top + uniform(3.2, 4.0), uniform(-0.6, 0.6)});
    t = legs.back().time_s + 30;
  }
  fs::create_directories(out / "dive");
  std::ofstream nav(out / "dive" / "nav.csv");
  nav << "time_s,lat,lon,depth_m,altitude_m,heading_deg,pitch_deg,roll_deg\n";
  nlohmann::json sightings = nlohmann::json::array();
  for (size_t k = 0; k < legs.size(); ++k) {
    const Leg& leg = legs[k];
    const Eigen::Vector2d bow(-std::sin(leg.heading), std::cos(leg.heading));  // the image's top on the seabed
    const Rigid pose = DownLookingCamera(leg.x, leg.y, leg.z, leg.heading);
    const std::string name = cv::format("dive_%08.3f", leg.time_s);
    WritePair(RenderStereoPair(scene, rig, pose, o.render, ++*noise_seed), out / "dive", name);
    sightings.push_back({{"pair", name}, {"time_s", leg.time_s}, {"in_navigation", k + 1 < legs.size()}});
    if (k + 1 == legs.size()) break;          // the navigation has ended
    for (int step = -5; step <= 5; ++step) {  // 0.5 m/s along the bow, straight and level
      const Eigen::Vector2d at = Eigen::Vector2d(leg.x, leg.y) + 0.5 * step * bow;
      const LatLon ll = earth.ToLatLon({at.x(), at.y()});
      nav << cv::format("%.3f,%.10f,%.10f,%.4f,%.4f,%.4f,0,0\n", leg.time_s + step, ll.lat, ll.lon,
                        o.dive_seabed_depth_m - leg.z, leg.z, compass(leg.heading));
    }
  }
  // The object's frame: the model's, the first overview pair's left camera.
  const Rigid& model = summary.overview.begin()->second;
  const Eigen::Vector3d p = model.translation(), x_axis = model.linear().col(0);
  const LatLon object = earth.ToLatLon({p.x(), p.y()});
  const nlohmann::json truth = {
      {"origin", {o.dive_origin_lat, o.dive_origin_lon}},
      {"seabed_depth_m", o.dive_seabed_depth_m},
      {"object",
       {{"lat", object.lat},
        {"lon", object.lon},
        {"position_m", {p.x(), p.y()}},
        {"depth_m", o.dive_seabed_depth_m - p.z()},
        {"heading_deg", std::fmod(std::atan2(x_axis.x(), x_axis.y()) * 180 / M_PI + 360, 360.0)}}},
      {"sightings", sightings}};
  std::ofstream(out / "truth" / "dive.json") << truth.dump(2) << "\n";
}

}  // namespace

void StereoSurveyOptions::Check() const {
  if (out_dir.empty()) throw InputError("", 0, "--out", "expected an output folder");
  if (views < 1 || views > 20) throw InputError("", 0, "--views", "expected 1 to 20 pairs");
  if (!(object_texture >= 0 && object_texture <= 2)) throw InputError("", 0, "--texture", "expected 0-2");
  if (!(approach_offset_m >= 0 && approach_offset_m <= 2)) throw InputError("", 0, "--offset", "expected 0-2 m");
  if (dive_sightings < 0 || dive_sightings > 50) throw InputError("", 0, "--dive", "expected 0 to 50 sightings");
  if (!(motion_sigma_m >= 0 && motion_sigma_m <= 1 && motion_sigma_deg >= 0 && motion_sigma_deg <= 10))
    throw InputError("", 0, "--motion-noise", "expected 0-1 m and 0-10 degrees");
  render.Check();
}

StereoCalibration SimulatedStereoRig() {
  StereoCalibration c;
  c.image_size = {1200, 900};
  c.K1 = c.K2 = cv::Matx33d(1040, 0, 599.5, 0, 1040, 449.5, 0, 0, 1);
  c.D1 = c.D2 = std::vector<double>(5, 0.0);
  // A 0.3 deg toe-in about the vertical axis, so that rectification is exercised.
  const double a = 0.3 * M_PI / 180;
  c.R = cv::Matx33d(std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a));
  c.T = cv::Vec3d(-0.25, 0, 0);
  c.Rectify();
  return c;
}

StereoSurveySummary SimulateStereoSurvey(const StereoSurveyOptions& options) {
  options.Check();
  const auto start = std::chrono::steady_clock::now();
  const fs::path out(options.out_dir);
  if (fs::exists(out) && !fs::is_empty(out) && !options.force)
    throw InputError(options.out_dir, 0, "--out", "folder is not empty (use --force to replace)");
  for (const char* sub : {"overview", "approach", "empty", "dive", "truth"}) fs::remove_all(out / sub);
  fs::create_directories(out / "truth");

  StereoSceneOptions scene_options;
  scene_options.seed = options.seed;
  scene_options.object_texture = options.object_texture;
  const StereoScene scene = StereoScene::Wellhead(scene_options);
  const StereoCalibration rig = SimulatedStereoRig();
  SaveStereoCalibration(rig, (out / "stereo.yaml").string());

  std::mt19937_64 rng(options.seed * 104729 + 3);
  const auto uniform = [&](double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); };
  StereoSurveySummary summary;
  summary.layout = scene.layout;
  const double top = scene.top_z_m;
  // The rig's centre (between the cameras) is placed; the left camera sits
  // half a baseline to the left of it.
  const auto left_camera = [&](double x, double y, double z, double heading) {
    Rigid rig_pose = DownLookingCamera(x, y, z, heading);
    rig_pose.translation() -= rig_pose.linear().col(0) * 0.125;
    return rig_pose;
  };
  for (int k = 0; k < options.views; ++k) {
    const double angle = uniform(0, 2 * M_PI), offset = k == 0 ? uniform(0, 0.2) : uniform(0.3, 0.6);
    summary.overview[cv::format("ov_%03d", k + 1)] = left_camera(offset * std::cos(angle), offset * std::sin(angle),
                                                                 top + 3.6 + uniform(-0.1, 0.1), uniform(-0.35, 0.35));
  }
  double heading = uniform(-M_PI / 4, M_PI / 4);
  const double first_angle = uniform(0, 2 * M_PI), first_offset = uniform(0, options.approach_offset_m);
  Eigen::Vector2d xy(first_offset * std::cos(first_angle), first_offset * std::sin(first_angle));
  for (int k = 0; k < options.views; ++k) {
    if (k > 0) {
      // 0.3-0.8 m to the next pair, drifting back towards the object.
      const double step = uniform(0.3, 0.8), dir = uniform(0, 2 * M_PI);
      Eigen::Vector2d next = xy + step * Eigen::Vector2d(std::cos(dir), std::sin(dir));
      if (next.norm() > options.approach_offset_m + 0.3)
        next = xy - step * Eigen::Vector2d(std::cos(dir), std::sin(dir));
      xy = next;
      heading += uniform(-0.2, 0.2);
    }
    summary.approach[cv::format("ap_%03d", k + 1)] = left_camera(xy.x(), xy.y(), top + uniform(3.0, 4.2), heading);
  }

  nlohmann::json poses = {{"overview", nlohmann::json::object()}, {"approach", nlohmann::json::object()}};
  uint64_t noise_seed = options.seed * 1000003;
  for (const auto& [group, set] : {std::pair{"overview", &summary.overview}, std::pair{"approach", &summary.approach}})
    for (const auto& [name, pose] : *set) {
      WritePair(RenderStereoPair(scene, rig, pose, options.render, ++noise_seed), out / group, name);
      poses[group][name] = RigidToJson(pose);
    }
  // A pair over bare seabed, 8 m from the object.
  const Rigid empty_pose = left_camera(8, -6, top + 3.6, uniform(-1, 1));
  WritePair(RenderStereoPair(scene, rig, empty_pose, options.render, ++noise_seed), out / "empty", "em_001");
  poses["empty"] = {{"em_001", RigidToJson(empty_pose)}};

  std::ofstream(out / "truth" / "poses.json") << poses.dump(2) << "\n";
  // The rig's path as the vehicle's navigation measures it (stereo-locate --motion): the true poses,
  // each off by the navigation's noise, from a generator of its own so the scene does not change.
  std::mt19937_64 nav_rng(options.seed * 7919 + 17);
  std::normal_distribution<double> gauss;
  nlohmann::json measured = nlohmann::json::object();
  for (const auto& [name, pose] : summary.approach) {
    Eigen::Matrix<double, 6, 1> noise;
    for (int i = 0; i < 3; ++i) noise[i] = gauss(nav_rng) * options.motion_sigma_deg * M_PI / 180;
    for (int i = 3; i < 6; ++i) noise[i] = gauss(nav_rng) * options.motion_sigma_m;
    measured[name] = RigidToJson(pose * RigidFromVector(noise));
  }
  std::ofstream(out / "motion.json") << nlohmann::json{{"world_from_camera", measured},
                                                       {"sigma_m", std::max(options.motion_sigma_m, 1e-4)},
                                                       {"sigma_deg", std::max(options.motion_sigma_deg, 1e-3)}}
                                            .dump(2)
                                     << "\n";
  std::ofstream check(out / "truth" / "check_points.csv");
  check << "x,y,z\n";
  for (const auto& [name, p] : scene.check_points) check << cv::format("%.6f,%.6f,%.6f\n", p.x(), p.y(), p.z());
  // The same points in --object-frame form: exact pixels in the first overview pair (raw = rectified
  // up to the rig's toe-in; ProjectRaw gives the raw ones a user would click).
  std::ofstream drawing(out / "truth" / "object_points.csv");
  drawing << "name,x,y,z,u_left,v_left,u_right,v_right\n";
  const Rigid first_from_scene = summary.overview.begin()->second.inverse();
  int index = 0;
  for (const auto& [name, p] : scene.check_points) {
    const Eigen::Vector3d c = first_from_scene * p;
    const cv::Point2d l = rig.ProjectRaw(c, false), r = rig.ProjectRaw(c, true);
    drawing << cv::format("%s_%d,%.6f,%.6f,%.6f,%.4f,%.4f,%.4f,%.4f\n", name.c_str(), ++index, p.x(), p.y(), p.z(), l.x,
                          l.y, r.x, r.y);
  }
  if (options.dive_sightings > 0) SimulateDive(options, scene, rig, summary, out, &noise_seed);
  nlohmann::json info = {{"format", "seamap-stereo-scene"},
                         {"seed", options.seed},
                         {"views", options.views},
                         {"layout", scene.layout},
                         {"object_top_z_m", top},
                         {"object_texture", options.object_texture},
                         {"beta_per_m", options.render.beta_per_m},
                         {"noise_sigma", options.render.noise_sigma},
                         {"blur_sigma_px", options.render.blur_sigma_px},
                         {"supersample", options.render.supersample}};
  std::ofstream(out / "scene.json") << info.dump(2) << "\n";
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace seamap
