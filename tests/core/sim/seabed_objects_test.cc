#include "core/sim/seabed_objects.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "core/sim/survey_simulator.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {
namespace fs = std::filesystem;

// Distance between convex polygons computed independently of the placer:
// 0 when a vertex of one lies inside the other, else the least vertex-edge distance.
double Gap(const std::vector<LocalXY>& a, const std::vector<LocalXY>& b) {
  auto contour = [](const std::vector<LocalXY>& p) {
    std::vector<cv::Point2f> c;
    for (const LocalXY& q : p) c.emplace_back(static_cast<float>(q.east), static_cast<float>(q.north));
    return c;
  };
  const auto ca = contour(a), cb = contour(b);
  double best = 1e9;
  for (const cv::Point2f& p : ca) best = std::min(best, std::max(0.0, cv::pointPolygonTest(cb, p, true) * -1));
  for (const cv::Point2f& p : cb) best = std::min(best, std::max(0.0, cv::pointPolygonTest(ca, p, true) * -1));
  return best;
}

std::vector<cv::Rect2d> Lanes() {  // three overlapping 2.5 m wide frame strips, 10 m long
  std::vector<cv::Rect2d> r;
  for (int lane = 0; lane < 3; ++lane)
    for (int k = 0; k < 10; ++k) r.emplace_back(2.2 * lane, k * 1.0, 2.5, 1.6);
  return r;
}

TEST(SeabedObjectsTest, PlacementKeepsClassesSizesSpacingAndCoverage) {
  const auto objects = PlaceSeabedObjects(12, Lanes(), 7);
  ASSERT_EQ(objects.size(), 12u);
  const double lo[] = {0.5, 0.4, 1.0, 0.3, 0.17}, hi[] = {1.0, 1.7, 3.4, 1.6, 0.85};
  for (size_t i = 0; i < objects.size(); ++i) {
    const SeabedObject& o = objects[i];
    EXPECT_EQ(o.class_id, static_cast<int>(i % 5));
    EXPECT_GE(o.size_m(), lo[o.class_id]) << SeabedObjectClasses()[o.class_id];
    EXPECT_LE(o.size_m(), hi[o.class_id]) << SeabedObjectClasses()[o.class_id];
    // The truth centre is the centre of the footprint's box, and the box lies inside the survey.
    double e0 = 1e9, e1 = -1e9, n0 = 1e9, n1 = -1e9;
    for (const LocalXY& p : o.footprint_m)
      e0 = std::min(e0, p.east), e1 = std::max(e1, p.east), n0 = std::min(n0, p.north), n1 = std::max(n1, p.north);
    EXPECT_NEAR(o.centre_east_m, (e0 + e1) / 2, 1e-9);
    EXPECT_NEAR(o.centre_north_m, (n0 + n1) / 2, 1e-9);
    EXPECT_NEAR(o.size_m(), std::max(e1 - e0, n1 - n0), 1e-9);
    EXPECT_GE(e0, 0);
    EXPECT_LE(e1, 6.9);
    EXPECT_GE(n0, 0);
    EXPECT_LE(n1, 10.6);
    for (size_t j = 0; j < i; ++j) EXPECT_GE(Gap(o.footprint_m, objects[j].footprint_m), 1.0 - 1e-6) << i << " " << j;
  }
  // An anchor's box centre is not its centroid: the stock end and the fluke end differ.
  const SeabedObject& anchor = objects[3];
  cv::Point2d centroid(0, 0);
  for (const LocalXY& p : anchor.footprint_m) centroid += cv::Point2d(p.east, p.north);
  centroid /= static_cast<double>(anchor.footprint_m.size());
  EXPECT_GT(std::hypot(centroid.x - anchor.centre_east_m, centroid.y - anchor.centre_north_m), 1e-3);
}

TEST(SeabedObjectsTest, SameSeedSameObjects) {
  const auto a = PlaceSeabedObjects(8, Lanes(), 3), b = PlaceSeabedObjects(8, Lanes(), 3);
  const auto c = PlaceSeabedObjects(8, Lanes(), 4);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].centre_east_m, b[i].centre_east_m);
    EXPECT_EQ(a[i].centre_north_m, b[i].centre_north_m);
    EXPECT_EQ(a[i].angle_rad, b[i].angle_rad);
  }
  EXPECT_NE(a[0].centre_east_m, c[0].centre_east_m);
}

TEST(SeabedObjectsTest, TooManyObjectsIsAnErrorNamingTheOption) {
  try {
    PlaceSeabedObjects(200, Lanes(), 1);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--objects"), std::string::npos) << e.what();
  }
}

// Paints one object of each class into a gray and a 16-bit colour seabed and
// checks that the changed pixels are where the truth box says.
TEST(SeabedObjectsTest, PaintedObjectsLieInTheirTruthBoxes) {
  for (const bool color : {false, true}) {
    SeabedTexture tex;
    tex.res_m = 0.004;
    tex.east_min = -0.5, tex.north_max = 11;
    tex.image = MakeProceduralTexture({2000, 3000}, tex.res_m, color, color ? 16 : 8, 2);
    const cv::Mat plain = tex.image.clone();
    const auto objects = PlaceSeabedObjects(5, Lanes(), 11);
    PaintSeabedObjects(objects, &tex);
    ASSERT_EQ(tex.image.type(), plain.type());
    cv::Mat diff;
    cv::absdiff(tex.image, plain, diff);
    if (color) cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
    diff.convertTo(diff, CV_8U, color ? 1 / 257.0 : 1.0);
    cv::Mat1b changed = diff > 10;
    for (const SeabedObject& o : objects) {
      const std::string name = SeabedObjectClasses()[o.class_id];
      const int x0 = static_cast<int>(std::lround(tex.Column(o.centre_east_m - o.box_width_m / 2) + 0.5));
      const int x1 = static_cast<int>(std::lround(tex.Column(o.centre_east_m + o.box_width_m / 2) + 0.5));
      const int y0 = static_cast<int>(std::lround(tex.Row(o.centre_north_m + o.box_height_m / 2) + 0.5));
      const int y1 = static_cast<int>(std::lround(tex.Row(o.centre_north_m - o.box_height_m / 2) + 0.5));
      const cv::Rect box(x0, y0, x1 - x0, y1 - y0);
      // Most of an object's footprint is changed (an anchor is thin, its footprint the hull: less).
      std::vector<cv::Point2f> hull;
      for (const LocalXY& p : o.footprint_m)
        hull.emplace_back(static_cast<float>(p.east / tex.res_m), static_cast<float>(p.north / tex.res_m));
      const double fraction = cv::countNonZero(changed(box)) / cv::contourArea(hull);
      EXPECT_GT(fraction, o.class_id == 3 ? 0.2 : 0.5) << name << " color " << color;
      // Changes around it start at the box's north-west edges (the shadow falls south-east).
      // 15 px north-west of the box: no neighbour's shadow reaches there; 0.8 m south-east: its own shadow.
      const cv::Rect around = cv::Rect(x0 - 15, y0 - 15, box.width + 215, box.height + 215) &
                              cv::Rect(0, 0, tex.image.cols, tex.image.rows);
      const cv::Rect seen = cv::boundingRect(changed(around)) + around.tl();
      EXPECT_NEAR(seen.x, x0, 2) << name << " color " << color;
      EXPECT_NEAR(seen.y, y0, 2) << name << " color " << color;
      EXPECT_GE(seen.br().x, x1 - 2) << name;
      EXPECT_GE(seen.br().y, y1 - 2) << name;
      changed(around).setTo(0);
    }
    EXPECT_EQ(cv::countNonZero(changed), 0) << "changes away from every object, color " << color;
  }
}

TEST(SeabedObjectsTest, SurveyWritesTruthAndPaintsTheTexture) {
  const testing::TempDir dir;
  auto options = [&](const std::string& name, int objects) {
    SimulationOptions o;
    o.out_dir = (dir.path() / name).string();
    o.camera = CameraFromFocalLength(8.0, 12.9 * 696 / 240, 240, 180);
    o.trajectory.frames = 60;
    o.line_length_m = 6;
    o.texture_res_m = 0.005;
    o.objects = objects;
    o.seed = 5;
    return o;
  };
  SimulateSurvey(options("with", 3));
  SimulateSurvey(options("without", 0));
  std::ifstream csv(dir.path() / "with/truth/objects.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "class,lat,lon,x_m,y_m,size_m");
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_EQ(rows, 3);
  EXPECT_FALSE(fs::exists(dir.path() / "without/truth/objects.csv"));

  std::ifstream json_in(dir.path() / "with/truth/objects.json");
  const nlohmann::json j = nlohmann::json::parse(json_in);
  ASSERT_EQ(j["objects"].size(), 3u);
  std::ifstream tex_json_in(dir.path() / "with/truth/texture.json");
  const nlohmann::json tj = nlohmann::json::parse(tex_json_in);
  SeabedTexture geo;
  geo.res_m = tj["res_m"], geo.east_min = tj["east_min"], geo.north_max = tj["north_max"];
  const cv::Mat with = cv::imread((dir.path() / "with/truth/texture.png").string(), cv::IMREAD_UNCHANGED);
  const cv::Mat without = cv::imread((dir.path() / "without/truth/texture.png").string(), cv::IMREAD_UNCHANGED);
  ASSERT_EQ(with.size(), without.size());
  cv::Mat1b changed = cv::abs(with - without) + cv::abs(without - with) > 10;
  const LocalFrame frame(SimulationOptions().origin);
  for (const auto& o : j["objects"]) {
    const auto& ring = o["footprint_lonlat"];
    EXPECT_EQ(ring.front(), ring.back()) << "closed ring";
    const LocalXY xy = frame.FromLatLon({o["lat"].get<double>(), o["lon"].get<double>()});
    EXPECT_NEAR(xy.east, o["x_m"].get<double>(), 1e-4);
    EXPECT_NEAR(xy.north, o["y_m"].get<double>(), 1e-4);
    const double half_w = o["box_m"][0].get<double>() / 2, half_h = o["box_m"][1].get<double>() / 2;
    const cv::Rect box(static_cast<int>(geo.Column(xy.east - half_w) + 0.5),
                       static_cast<int>(geo.Row(xy.north + half_h) + 0.5), static_cast<int>(2 * half_w / geo.res_m),
                       static_cast<int>(2 * half_h / geo.res_m));
    EXPECT_GT(cv::countNonZero(changed(box)), 0.08 * box.area()) << o["class"];
  }
}

}  // namespace
}  // namespace seamap
