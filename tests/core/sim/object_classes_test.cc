// Issue 32's simulated conditions: a class the shipped model does not know
// (drum), objects partly under sediment (--bury), look-alikes that are no
// object (--clutter) and motion blur (--blur); none of them changes a survey
// made without them.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/sim/seabed_objects.h"
#include "core/sim/survey_simulator.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {
namespace fs = std::filesystem;

std::vector<cv::Rect2d> Lanes() {  // three overlapping 2.5 m wide frame strips, 10 m long
  std::vector<cv::Rect2d> r;
  for (int lane = 0; lane < 3; ++lane)
    for (int k = 0; k < 10; ++k) r.emplace_back(2.2 * lane, k * 1.0, 2.5, 1.6);
  return r;
}

SeabedTexture Texture(bool color) {
  SeabedTexture tex;
  tex.res_m = 0.004;
  tex.east_min = -0.5, tex.north_max = 11;
  tex.image = MakeProceduralTexture({2000, 3000}, tex.res_m, color, 8, 2);
  return tex;
}

cv::Rect BoxPx(const SeabedTexture& tex, const SeabedObject& o) {
  const int x0 = static_cast<int>(std::lround(tex.Column(o.centre_east_m - o.box_width_m / 2) + 0.5));
  const int x1 = static_cast<int>(std::lround(tex.Column(o.centre_east_m + o.box_width_m / 2) + 0.5));
  const int y0 = static_cast<int>(std::lround(tex.Row(o.centre_north_m + o.box_height_m / 2) + 0.5));
  const int y1 = static_cast<int>(std::lround(tex.Row(o.centre_north_m - o.box_height_m / 2) + 0.5));
  return cv::Rect(x0, y0, x1 - x0, y1 - y0);
}

TEST(ObjectClassesTest, TheDefaultClassListIsTheFiveOfBefore) {
  const auto before = PlaceSeabedObjects(12, Lanes(), 7);
  const auto listed = PlaceSeabedObjects(12, Lanes(), 7, 1.0, {0, 1, 2, 3, 4});
  ASSERT_EQ(before.size(), listed.size());
  for (size_t i = 0; i < before.size(); ++i) {
    EXPECT_EQ(before[i].class_id, listed[i].class_id);
    EXPECT_EQ(before[i].centre_east_m, listed[i].centre_east_m);
    EXPECT_EQ(before[i].angle_rad, listed[i].angle_rad);
    EXPECT_EQ(before[i].shape_seed, listed[i].shape_seed);
  }
  EXPECT_EQ(ParseObjectClasses("tyre,crate,pipe,anchor,rock", "--object-classes"), (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(ParseObjectClasses("drum", "--object-classes"), std::vector<int>{5});
  EXPECT_EQ(SimulatedObjectClasses().at(5), "drum");
}

TEST(ObjectClassesTest, BadClassListsNameTheOption) {
  for (const std::string bad : {"tyre,barrel", "drum,drum", "", "tyre,,rock"}) {
    try {
      ParseObjectClasses(bad, "--object-classes");
      FAIL() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--object-classes"), std::string::npos) << e.what();
    }
  }
}

TEST(ObjectClassesTest, DrumsAreBarrelSizedRustyAndLieOrStand) {
  const auto drums = PlaceSeabedObjects(14, Lanes(), 21, 0.6, {5});
  ASSERT_EQ(drums.size(), 14u);
  int standing = 0;
  SeabedTexture tex = Texture(true);
  const cv::Mat plain = tex.image.clone();
  PaintSeabedObjects(drums, &tex);
  for (const SeabedObject& o : drums) {
    EXPECT_EQ(o.class_name(), "drum");
    EXPECT_FALSE(o.negative());
    standing += o.standing;
    EXPECT_NEAR(o.width_m, 0.59, 0.021);  // the diameter
    if (o.standing) {
      EXPECT_NEAR(o.size_m(), o.width_m, 0.01) << "a disc from above";
      EXPECT_NEAR(o.height_m, 0.89, 0.031);
    } else {
      EXPECT_NEAR(o.length_m, 0.89, 0.031);
      EXPECT_GE(o.size_m(), 0.6);
      EXPECT_LE(o.size_m(), std::hypot(0.92, 0.61) + 1e-9);
    }
    // Rust: the painted body is redder than it is blue, where the seabed is not.
    const cv::Rect box = BoxPx(tex, o);
    const cv::Rect core(box.x + box.width / 3, box.y + box.height / 3, box.width / 3, box.height / 3);
    const cv::Scalar body = cv::mean(tex.image(core)), seabed = cv::mean(plain(core));
    EXPECT_GT(body[2] / body[0], 1.3 * seabed[2] / seabed[0])
        << "drum at " << o.centre_east_m << "," << o.centre_north_m;
  }
  EXPECT_GT(standing, 0);
  EXPECT_LT(standing, 14);
}

TEST(ObjectClassesTest, BuriedObjectsShowLessOfThemselves) {
  const auto objects = PlaceSeabedObjects(5, Lanes(), 11);
  auto changed_in_boxes = [&](double bury) {
    SeabedTexture tex = Texture(false);
    const cv::Mat plain = tex.image.clone();
    std::vector<SeabedObject> painted = objects;
    for (SeabedObject& o : painted) o.buried_fraction = bury;
    PaintSeabedObjects(painted, &tex);
    std::vector<int> counts;
    for (const SeabedObject& o : painted) {
      cv::Mat diff;
      cv::absdiff(tex.image(BoxPx(tex, o)), plain(BoxPx(tex, o)), diff);
      counts.push_back(cv::countNonZero(diff > 25));
    }
    return counts;
  };
  const std::vector<int> whole = changed_in_boxes(0), half = changed_in_boxes(0.5), most = changed_in_boxes(0.8);
  for (size_t i = 0; i < objects.size(); ++i) {
    const std::string name = objects[i].class_name();
    EXPECT_LT(half[i], 0.95 * whole[i]) << name;
    EXPECT_LT(most[i], half[i]) << name;
    EXPECT_GT(most[i], 0) << name << ": something still shows";
  }
}

TEST(ObjectClassesTest, ClutterKeepsAwayFromObjectsAndIsNoLabel) {
  const auto objects = PlaceSeabedObjects(6, Lanes(), 3);
  const auto clutter = PlaceClutter(9, Lanes(), 3, objects);
  ASSERT_EQ(clutter.size(), 9u);
  for (size_t i = 0; i < clutter.size(); ++i) {
    EXPECT_TRUE(clutter[i].negative());
    EXPECT_EQ(clutter[i].class_name(), ClutterKinds()[i % 3]);
    for (const SeabedObject& o : objects)
      EXPECT_GT(std::hypot(o.centre_east_m - clutter[i].centre_east_m, o.centre_north_m - clutter[i].centre_north_m),
                0.5);
  }
  // The objects of a seed do not move for clutter (their own random stream).
  const auto again = PlaceSeabedObjects(6, Lanes(), 3);
  EXPECT_EQ(again[5].centre_east_m, objects[5].centre_east_m);

  const testing::TempDir dir;
  std::vector<SeabedObject> all = objects;
  all.insert(all.end(), clutter.begin(), clutter.end());
  SaveObjectsTruth(all, LocalFrame({43.1, 131.9}), dir.path().string());
  std::ifstream csv(dir.path() / "objects.csv");
  int rows = -1;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 6) << "clutter is not in objects.csv";
  std::ifstream in(dir.path() / "objects.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["objects"].size(), 6u);
  ASSERT_EQ(j["negatives"].size(), 9u);
  EXPECT_EQ(j["negatives"][0]["class"], "rock_ring");
  EXPECT_TRUE(j["negatives"][0]["negative"].get<bool>());
  EXPECT_EQ(j["classes"].size(), 5u) << "no drum painted";
  try {
    PlaceClutter(500, Lanes(), 3, objects);
    FAIL() << "500 clutter pieces fit";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--clutter"), std::string::npos) << e.what();
  }
}

std::string Bytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

SimulationOptions SmallSurvey(const fs::path& out) {
  SimulationOptions o;
  o.out_dir = out.string();
  o.camera = CameraFromFocalLength(8.0, 12.9 * 696 / 240, 240, 180);
  o.trajectory.frames = 60;
  o.line_length_m = 6;
  o.texture_res_m = 0.005;
  o.objects = 3;
  o.color = true;
  o.seed = 9;
  return o;
}

TEST(ObjectClassesTest, SurveysWithoutTheNewOptionsAreUnchangedAndWithThemDiffer) {
  const testing::TempDir dir;
  SimulateSurvey(SmallSurvey(dir.path() / "plain"));
  SimulationOptions listed = SmallSurvey(dir.path() / "listed");
  listed.object_classes = {0, 1, 2, 3, 4};
  SimulateSurvey(listed);
  for (const char* f : {"truth/texture.png", "truth/objects.json", "truth/objects.csv", "photo/frame_000020.png"})
    EXPECT_EQ(Bytes(dir.path() / "plain" / f), Bytes(dir.path() / "listed" / f)) << f;

  SimulationOptions drums = SmallSurvey(dir.path() / "drums");
  drums.object_classes = {5, 0};
  drums.clutter = 2;
  drums.bury_fraction = 0.3;
  drums.degradations.blur_px = 6;
  SimulateSurvey(drums);
  std::ifstream in(dir.path() / "drums/truth/objects.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j["objects"].size(), 3u);
  EXPECT_EQ(j["objects"][0]["class"], "drum");
  EXPECT_EQ(j["objects"][0]["class_id"], 5);
  EXPECT_EQ(j["objects"][1]["class"], "tyre");
  EXPECT_DOUBLE_EQ(j["objects"][0]["buried_fraction"].get<double>(), 0.3);
  EXPECT_EQ(j["classes"].back(), "drum");
  EXPECT_EQ(j["negatives"].size(), 2u);
  std::ifstream sin(dir.path() / "drums/survey.json");
  const nlohmann::json survey = nlohmann::json::parse(sin);
  EXPECT_EQ(survey["object_classes"], nlohmann::json({"drum", "tyre"}));
  EXPECT_EQ(survey["degradations"]["blur_px"], 6.0);

  // Motion blur smooths along the rows, not across them.
  SimulationOptions sharp = SmallSurvey(dir.path() / "sharp");
  sharp.objects = 0;
  SimulateSurvey(sharp);
  SimulationOptions blurred = sharp;
  blurred.out_dir = (dir.path() / "blurred").string();
  blurred.degradations.blur_px = 6;
  SimulateSurvey(blurred);
  auto energy = [](const fs::path& p, int dx, int dy) {
    cv::Mat g = cv::imread(p.string(), cv::IMREAD_GRAYSCALE), d;
    cv::Sobel(g, d, CV_32F, dx, dy);
    return cv::norm(d, cv::NORM_L1);
  };
  const fs::path s = dir.path() / "sharp/photo/frame_000020.png", b = dir.path() / "blurred/photo/frame_000020.png";
  const double along = energy(b, 1, 0) / energy(s, 1, 0), across = energy(b, 0, 1) / energy(s, 0, 1);
  EXPECT_LT(along, 0.8 * across) << along << " " << across;
}

}  // namespace
}  // namespace seamap
