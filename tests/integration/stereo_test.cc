// simulate-stereo -> stereo-model -> stereo-locate end to end, checked against
// the scene's exact truth with the seed paper's error (check points mapped
// with the estimated and the true pose), and the commands' answers to bad
// input and to pairs without the object.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "core/geo/local_frame.h"
#include "core/mission/mission_metadata.h"
#include "core/stereo/object_georef.h"
#include "core/stereo/rigid_transform.h"
#include "core/tiles/modem_record.h"
#include "core/tiles/tile_store.h"
#include "tests/integration/survey_fixture.h"
#include "tests/testing/child_process.h"

// After Eigen: resolv.h, which httplib includes, defines _res, an Eigen parameter name.
#include <httplib.h>

namespace seamap {
namespace {

namespace fs = std::filesystem;
using testing::Seamap;

struct Scene {
  std::unique_ptr<testing::TempDir> dir;
  std::string root, calib, model;
};

// One scene and its model per test binary (seed 1, three overview and three approach pairs;
// one sample per pixel to keep the test quick: the bench renders 2 x 2).
const Scene& SharedScene() {
  static Scene scene = [] {
    Scene s;
    s.dir = std::make_unique<testing::TempDir>();
    s.root = (s.dir->path() / "scene").string();
    s.calib = s.root + "/stereo.yaml";
    s.model = (s.dir->path() / "object.json").string();
    std::string log;
    if (Seamap("simulate-stereo --out " + s.root + " --seed 1 --views 3 --supersample 1", &log) != 0)
      ADD_FAILURE() << "simulate-stereo failed:\n" << log;
    if (Seamap("stereo-model --calib " + s.calib + " --pairs " + s.root + "/overview --out " + s.model, &log) != 0)
      ADD_FAILURE() << "stereo-model failed:\n" << log;
    return s;
  }();
  return scene;
}

nlohmann::json ReadJson(const std::string& path) {
  return nlohmann::json::parse(std::ifstream(path));
}

std::vector<Eigen::Vector3d> CheckPoints(const std::string& root) {
  std::ifstream in(root + "/truth/check_points.csv");
  std::string line;
  std::getline(in, line);
  std::vector<Eigen::Vector3d> out;
  double x, y, z;
  char c1, c2;
  while (in >> x >> c1 >> y >> c2 >> z) out.emplace_back(x, y, z);
  return out;
}

// Check-point error (m) of pose.json against truth: the model frame is the first overview pair's left camera.
double PoseError(const Scene& s, const nlohmann::json& pose) {
  const auto truth = ReadJson(s.root + "/truth/poses.json");
  const Rigid scene_from_model = RigidFromJson(truth["overview"]["ov_001"], "truth", "ov_001");
  const std::string pair = pose["views"][0]["pair"];
  const Rigid truth_pose = RigidFromJson(truth["approach"][pair], "truth", pair);
  const Rigid estimate = scene_from_model * RigidFromJson(pose["object_from_camera"], "pose", "object_from_camera");
  return CheckPointError(estimate, truth_pose, CheckPoints(s.root));
}

nlohmann::json Locate(const Scene& s, const std::string& extra, const std::string& pairs = "approach") {
  const std::string out = (s.dir->path() / "pose.json").string();
  std::string log;
  EXPECT_EQ(Seamap("stereo-locate --calib " + s.calib + " --model " + s.model + " --pairs " + s.root + "/" + pairs +
                       " --out " + out + " " + extra,
                   &log),
            0)
      << log;
  std::printf("%s", log.c_str());
  return ReadJson(out);
}

// A located object becomes a detection of the mission: the vehicle's
// navigation at the pair's time and the rig's mounting place it on the Earth.
TEST(Stereo, ALocatedObjectIsStoredAsADetectionWithPositionHeadingAndDepth) {
  const Scene& s = SharedScene();
  const auto& survey = testing::SharedSurvey("stereo_map", "--frames 12 --line-length 2 --seed 3");
  const std::string map = (s.dir->path() / "mission.mbtiles").string();
  std::string log;
  ASSERT_EQ(Seamap(survey.BuildArgs() + " --out " + map + " --overwrite", &log), 0) << log;
  // The vehicle: 5 m east, 7 m north of the mission origin, 40 m deep, bow at 35 degrees, pitched and rolled.
  const std::string nav = (s.dir->path() / "rov_nav.csv").string();
  std::ofstream(nav) << "time_s,x_m,y_m,depth_m,altitude_m,heading_deg,pitch_deg,roll_deg\n"
                     << "100,5,7,40,3,35,4,-3\n102,5,7,40,3,35,4,-3\n";
  const std::string where = " --nav " + nav + " --time 101 --rig-offset 0.8,0.1,0.3 --map " + map;
  // The operator's console is already serving the map: it shows the object without a restart.
  testing::ChildProcess serve({testing::SeamapBinary(), "serve", map, "--host", "127.0.0.1", "--port", "0"},
                              (s.dir->path() / "serve.err").string());
  const auto serving = serve.WaitForLine("serving", std::chrono::seconds(20));
  ASSERT_TRUE(serving) << serve.output();
  const nlohmann::json pose = Locate(s, "--views 1" + where);
  ASSERT_TRUE(pose["found"].get<bool>()) << pose.dump();
  httplib::Client api("127.0.0.1", testing::PortFromServingLine(*serving));
  nlohmann::json served;
  for (int tries = 0; tries < 100 && served.empty(); ++tries) {
    auto res = api.Get("/api/detections?source=stereo");
    ASSERT_TRUE(res);
    served = nlohmann::json::parse(res->body)["features"];
    if (served.empty()) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  ASSERT_EQ(served.size(), 1u) << "the running server never showed the located object";
  EXPECT_NEAR(served[0]["properties"]["heading_deg"].get<double>(), pose["geo"]["heading_deg"].get<double>(), 1e-6);

  // Expected: the true pose of the pair used, carried through the same mounting and navigation.
  const auto truth = ReadJson(s.root + "/truth/poses.json");
  const std::string pair = pose["views"][0]["pair"];
  const Rigid model_from_camera = RigidFromJson(truth["overview"]["ov_001"], "truth", "ov_001").inverse() *
                                  RigidFromJson(truth["approach"][pair], "truth", pair);
  VehiclePose vehicle;
  vehicle.east_m = 5, vehicle.north_m = 7, vehicle.depth_m = 40, vehicle.altitude_m = 3;
  vehicle.heading_deg = 35, vehicle.pitch_deg = 4, vehicle.roll_deg = -3;
  RigMount mount;
  mount.offset_m = {0.8, 0.1, 0.3};
  auto store = OpenExistingMap(map, false);
  const std::optional<LatLon> origin = ReadMissionMetadata(*store).origin;  // local navigation is relative to it
  ASSERT_TRUE(origin);
  const LocalFrame frame(*origin);
  const PlacedObject expected = PlaceObject(model_from_camera, mount, vehicle, frame);

  std::vector<Detection> stereo;
  for (const Detection& d : store->Records().Detections())
    if (d.source == "stereo") stereo.push_back(d);
  ASSERT_EQ(stereo.size(), 1u);
  const Detection& d = stereo[0];
  const LocalXY at = frame.FromLatLon(d.position);
  EXPECT_LT(std::hypot(at.east - expected.local.east, at.north - expected.local.north), 0.01);
  ASSERT_TRUE(d.depth_m && d.heading_deg);
  EXPECT_NEAR(*d.depth_m, expected.depth_m, 0.01);
  EXPECT_NEAR(*d.heading_deg, expected.heading_deg, 0.5);
  EXPECT_EQ(d.class_name, pose["model"].get<std::string>());
  EXPECT_EQ(d.status, "unconfirmed");
  EXPECT_NEAR(pose["geo"]["heading_deg"].get<double>(), *d.heading_deg, 1e-9);
  // The acoustic modem's record carries the heading (360/256 degree steps).
  const ModemRecord r = ModemRecordOf(d, 0, std::nullopt);
  ASSERT_TRUE(r.heading_valid());
  EXPECT_LT(std::abs(std::remainder(r.heading * 360.0 / 256 - *d.heading_deg, 360.0)), 360.0 / 512 + 1e-9);

  // Located again: the same detection, updated, not a second one.
  Locate(s, "--views 1" + where);
  int count = 0;
  for (const Detection& again : OpenExistingMap(map, false)->Records().Detections())
    if (again.source == "stereo") {
      ++count;
      EXPECT_EQ(again.id, d.id);
    }
  EXPECT_EQ(count, 1);

  // Where the vehicle was must be known, and inside the navigation's times.
  const std::string base = "stereo-locate --calib " + s.calib + " --model " + s.model + " --pairs " + s.root +
                           "/approach --out " + (s.dir->path() / "p.json").string();
  EXPECT_NE(Seamap(base + " --map " + map, &log), 0);
  EXPECT_NE(log.find("--map"), std::string::npos) << log;
  EXPECT_NE(Seamap(base + " --nav " + nav + " --time 500 --map " + map, &log), 0);
  EXPECT_NE(log.find("--time"), std::string::npos) << log;
  EXPECT_NE(log.find("outside the navigation"), std::string::npos) << log;
  EXPECT_NE(Seamap(base + " --nav " + nav + " --time 101 --rig sideways", &log), 0);
  EXPECT_NE(log.find("--rig"), std::string::npos) << log;
}

TEST(Stereo, ModelHoldsPointsInTheFirstOverviewFrame) {
  const Scene& s = SharedScene();
  const auto model = ReadJson(s.model);
  EXPECT_EQ(model["format"], "seamap-stereo-model");
  EXPECT_EQ(model["views"].size(), 3u);
  EXPECT_GT(model["points"].size(), 1000u);
  // The other overview pairs' poses agree with truth, relative to pair 1.
  const auto truth = ReadJson(s.root + "/truth/poses.json");
  const Rigid scene_from_model = RigidFromJson(truth["overview"]["ov_001"], "truth", "ov_001");
  for (const auto& v : model["views"]) {
    const Rigid est = scene_from_model * RigidFromJson(v["object_from_camera"], "model", "view");
    const Rigid tru = RigidFromJson(truth["overview"][v["pair"].get<std::string>()], "truth", "view");
    EXPECT_LT(CheckPointError(est, tru, CheckPoints(s.root)), 0.003) << v["pair"];
  }
}

TEST(Stereo, OneViewAndThreeViewsLocateTheObjectWithinThePapersErrors) {
  const Scene& s = SharedScene();
  const auto one = Locate(s, "--views 1");
  ASSERT_TRUE(one["found"].get<bool>()) << one.dump(2);
  EXPECT_EQ(one["views"].size(), 1u);
  const double e1 = PoseError(s, one);
  const auto three = Locate(s, "--views 3");
  ASSERT_TRUE(three["found"].get<bool>()) << three.dump(2);
  EXPECT_EQ(three["views"].size(), 3u);
  const double e3 = PoseError(s, three);
  std::printf("check-point error: one view %.3f mm, three views %.3f mm\n", 1000 * e1, 1000 * e3);
  EXPECT_LT(e1, 0.032);   // the paper's one-view figure
  EXPECT_LT(e3, 0.0028);  // the paper's three-view figure
  // The reported uncertainty is honest: the error is within 4 sigma of the
  // object's points, and the camera's position sigma (lever arm included) is larger.
  const double s3 = three["uncertainty"]["point_sigma_m"].get<double>();
  const auto sigma = three["uncertainty"]["position_sigma_m"];
  EXPECT_GT(s3, 0);
  EXPECT_LT(e3, 4 * s3 + 0.0003);
  EXPECT_GT(std::hypot(sigma[0].get<double>(), sigma[1].get<double>(), sigma[2].get<double>()), s3);
  EXPECT_GE(three["tie_points"].get<int>(), 10);

  // Pairs tied to the first by too few points stay out, saying so: the result is the first pair's own.
  const auto untied = Locate(s, "--views 3 --min-tie-points 1000000");
  ASSERT_TRUE(untied["found"].get<bool>()) << untied.dump(2);
  EXPECT_EQ(untied["views"].size(), 1u);
  ASSERT_EQ(untied["rejected"].size(), 2u);
  EXPECT_NE(untied["rejected"][1]["reason"].get<std::string>().find("points tie it to the other pairs"),
            std::string::npos)
      << untied.dump(2);
  EXPECT_NEAR(PoseError(s, untied), e1, 1e-6);
}

TEST(Stereo, TheRigsMotionFromNavigationHoldsThePairsTogether) {
  const Scene& s = SharedScene();
  const std::string motion = s.root + "/motion.json";  // the true path, 1 mm and 0.01 degree off per axis
  const auto held = Locate(s, "--views 3 --motion " + motion);
  ASSERT_TRUE(held["found"].get<bool>()) << held.dump(2);
  EXPECT_EQ(held["views"].size(), 3u);
  const double e = PoseError(s, held);
  std::printf("check-point error, three views held to the rig's motion: %.3f mm\n", 1000 * e);
  EXPECT_LT(e, 0.0028);
  EXPECT_LT(e, 4 * held["uncertainty"]["point_sigma_m"].get<double>() + 0.0003);

  // Pairs that no tie point joins still join when the motion holds them.
  const auto untied = Locate(s, "--views 3 --min-tie-points 1000000 --motion " + motion);
  ASSERT_TRUE(untied["found"].get<bool>()) << untied.dump(2);
  EXPECT_EQ(untied["views"].size(), 3u);

  // A motion file that is not one is refused, naming what is wrong.
  testing::TempDir dir;
  const std::string base = "stereo-locate --calib " + s.calib + " --model " + s.model + " --pairs " + s.root +
                           "/approach --views 3 --out " + (dir / "p.json").string() + " --motion ";
  std::string log;
  EXPECT_EQ(Seamap(base + (dir / "none.json").string(), &log), 2);
  EXPECT_NE(log.find("--motion"), std::string::npos) << log;
  nlohmann::json bad = ReadJson(motion);
  bad["world_from_camera"]["ap_002"][0][0] = 3.0;
  testing::WriteFile(dir / "bad.json", bad.dump());
  EXPECT_EQ(Seamap(base + (dir / "bad.json").string(), &log), 2);
  EXPECT_NE(log.find("world_from_camera.ap_002"), std::string::npos) << log;
  bad = ReadJson(motion);
  bad["sigma_m"] = -1;
  testing::WriteFile(dir / "sigma.json", bad.dump());
  EXPECT_EQ(Seamap(base + (dir / "sigma.json").string(), &log), 2);
  EXPECT_NE(log.find("sigma_m"), std::string::npos) << log;
}

TEST(Stereo, ObjectFrameFromDrawingPointsGivesPosesInTheDrawingFrame) {
  const Scene& s = SharedScene();
  testing::TempDir dir;
  const std::string model = (dir / "drawing.json").string(), pose = (dir / "pose.json").string();
  const std::string build = "stereo-model --calib " + s.calib + " --pairs " + s.root + "/overview --out " + model;
  std::string log;
  ASSERT_EQ(Seamap(build + " --object-frame " + s.root + "/truth/object_points.csv", &log), 0) << log;
  EXPECT_EQ(ReadJson(model)["frame"], "drawing");
  ASSERT_EQ(Seamap("stereo-locate --calib " + s.calib + " --model " + model + " --pairs " + s.root +
                       "/approach --views 1 --out " + pose,
                   &log),
            0)
      << log;
  const auto result = ReadJson(pose);
  ASSERT_TRUE(result["found"].get<bool>()) << result.dump(2);
  // No conversion: the pose is compared with the scene's truth directly.
  const auto truth = ReadJson(s.root + "/truth/poses.json");
  const Rigid estimate = RigidFromJson(result["object_from_camera"], "pose", "object_from_camera");
  const Rigid truth_pose = RigidFromJson(truth["approach"]["ap_001"], "truth", "ap_001");
  EXPECT_LT(CheckPointError(estimate, truth_pose, CheckPoints(s.root)), 0.0028);

  // Millimetres instead of metres, and points on a line, are errors naming the problem.
  std::ifstream in(s.root + "/truth/object_points.csv");
  std::string header, line, mm = "", collinear = "";
  std::getline(in, header);
  mm = collinear = header + "\n";
  for (int k = 0; std::getline(in, line); ++k) {
    std::stringstream row(line);
    std::vector<std::string> cells;
    std::string cell;
    while (std::getline(row, cell, ',')) cells.push_back(cell);
    mm += cells[0];
    for (size_t c = 1; c < cells.size(); ++c)
      mm += "," + (c <= 3 ? std::to_string(1000 * std::stod(cells[c])) : cells[c]);
    mm += "\n";
    collinear += cells[0] + "," + std::to_string(0.1 * k) + ",0,0," + cells[4] + "," + cells[5] + "," + cells[6] + "," +
                 cells[7] + "\n";
  }
  testing::WriteFile(dir / "mm.csv", mm);
  testing::WriteFile(dir / "line.csv", collinear);
  EXPECT_EQ(Seamap(build + " --object-frame " + (dir / "mm.csv").string(), &log), 2);
  EXPECT_NE(log.find("metres"), std::string::npos) << log;
  EXPECT_EQ(Seamap(build + " --object-frame " + (dir / "line.csv").string(), &log), 2);
  EXPECT_NE(log.find("collinear"), std::string::npos) << log;
}

TEST(Stereo, IcpBaselineGivesARightPoseOrSaysWhyNot) {
  // ICP registers the structure standing off the seabed; on this scene (seed 1)
  // it ends ~8 cm off, and its found rule must refuse that rather than report it.
  const Scene& s = SharedScene();
  const auto icp = Locate(s, "--views 1 --method icp");
  EXPECT_EQ(icp["method"], "icp");
  EXPECT_GT(icp["timing"]["registration_s"].get<double>(), 0);
  if (!icp["found"].get<bool>()) {
    EXPECT_TRUE(icp["object_from_camera"].is_null());
    EXPECT_NE(icp["reason"].get<std::string>().find("off the seabed plane"), std::string::npos) << icp.dump(2);
    return;
  }
  const double e = PoseError(s, icp);
  const double sigma_m = icp["uncertainty"]["point_sigma_m"].get<double>();
  std::printf("ICP check-point error %.1f mm, sigma %.1f mm\n", 1000 * e, 1000 * sigma_m);
  EXPECT_LT(e, 3 * sigma_m + 0.002);
}

TEST(Stereo, NoObjectInViewIsFoundFalseNotAWrongPose) {
  const Scene& s = SharedScene();
  const auto empty = Locate(s, "--views 1", "empty");
  EXPECT_FALSE(empty["found"].get<bool>()) << empty.dump(2);
  EXPECT_TRUE(empty["object_from_camera"].is_null());
  EXPECT_FALSE(empty["reason"].get<std::string>().empty());

  // Another object's model (seed 2: another layout, other textures) does not match this object.
  const std::string other = (s.dir->path() / "other").string(), other_model = other + "/object.json";
  std::string log;
  ASSERT_EQ(Seamap("simulate-stereo --out " + other + " --seed 2 --views 1 --supersample 1", &log), 0) << log;
  ASSERT_EQ(Seamap("stereo-model --calib " + other + "/stereo.yaml --pairs " + other + "/overview --out " + other_model,
                   &log),
            0)
      << log;
  const std::string out = (s.dir->path() / "other_pose.json").string();
  ASSERT_EQ(Seamap("stereo-locate --calib " + s.calib + " --model " + other_model + " --pairs " + s.root +
                       "/approach --views 3 --out " + out,
                   &log),
            0)
      << log;
  const auto wrong = ReadJson(out);
  EXPECT_FALSE(wrong["found"].get<bool>()) << wrong.dump(2);
  EXPECT_TRUE(wrong["object_from_camera"].is_null());
}

int RunFails(const std::string& args, std::string* log) {
  return Seamap(args, log);
}

TEST(Stereo, BadInputIsAnErrorNamingIt) {
  const Scene& s = SharedScene();
  testing::TempDir dir;
  std::string log;
  const std::string out = " --out " + (dir / "pose.json").string();
  const std::string base = "stereo-locate --model " + s.model + " --views 1" + out;

  // Calibration for another image size.
  std::string yaml;
  {
    std::ifstream in(s.calib);
    yaml.assign(std::istreambuf_iterator<char>(in), {});
  }
  std::string other = yaml;
  other.replace(other.find("image_width: 1200"), 17, "image_width: 1600");
  testing::WriteFile(dir / "other.yaml", other);
  EXPECT_EQ(RunFails(base + " --calib " + (dir / "other.yaml").string() + " --pairs " + s.root + "/approach", &log), 2);
  EXPECT_NE(log.find("1200x900"), std::string::npos) << log;

  // A pair without its right image.
  fs::create_directories(dir / "lonely");
  fs::copy_file(s.root + "/approach/ap_001_left.png", dir / "lonely/ap_001_left.png");
  EXPECT_EQ(RunFails(base + " --calib " + s.calib + " --pairs " + (dir / "lonely").string(), &log), 2);
  EXPECT_NE(log.find("no right image"), std::string::npos) << log;

  // Left and right swapped.
  fs::create_directories(dir / "swapped");
  fs::copy_file(s.root + "/approach/ap_001_left.png", dir / "swapped/ap_001_right.png");
  fs::copy_file(s.root + "/approach/ap_001_right.png", dir / "swapped/ap_001_left.png");
  EXPECT_EQ(RunFails(base + " --calib " + s.calib + " --pairs " + (dir / "swapped").string(), &log), 2);
  EXPECT_NE(log.find("swapped"), std::string::npos) << log;

  // Not an image.
  fs::create_directories(dir / "text");
  testing::WriteFile(dir / "text/x_left.png", "not a png");
  testing::WriteFile(dir / "text/x_right.png", "not a png");
  EXPECT_EQ(RunFails(base + " --calib " + s.calib + " --pairs " + (dir / "text").string(), &log), 2);
  EXPECT_NE(log.find("x_left.png"), std::string::npos) << log;

  // Not a model.
  testing::WriteFile(dir / "model.json", "{\"format\": \"something else\"}");
  EXPECT_EQ(RunFails("stereo-locate --model " + (dir / "model.json").string() + " --calib " + s.calib + " --pairs " +
                         s.root + "/approach" + out,
                     &log),
            2);
  EXPECT_NE(log.find("format"), std::string::npos) << log;
}

}  // namespace
}  // namespace seamap
