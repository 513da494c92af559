// Which windows and boxes a reviewed mission gives the trainer (issue 32).
#include "core/detect/training_windows.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

constexpr int kZ = 25, kT = 256;

// A detection whose box is (x0, y0)-(x1, y1) in global pixels at zoom 25.
Detection At(int64_t id, const std::string& cls, const std::string& source, const std::string& status, double x0,
             double y0, double x1, double y1, bool with_box = true) {
  Detection d;
  d.id = id;
  d.class_name = cls;
  d.source = source;
  d.status = status;
  d.position = PixelToLatLon({(x0 + x1) / 2, (y0 + y1) / 2}, kZ, kT);
  if (with_box)
    for (const auto& [x, y] : std::vector<std::pair<double, double>>{{x0, y0}, {x0, y1}, {x1, y1}, {x1, y0}, {x0, y0}})
      d.box.push_back(PixelToLatLon({x, y}, kZ, kT));
  return d;
}

// A base window of zoom 25 far from the world's edges: tiles 1000..1002.
constexpr double kX = 1000.0 * kT, kY = 2000.0 * kT;

TrainingPlan Plan(const std::vector<Detection>& detections, double empty = 0,
                  const std::vector<WindowKey>& candidates = {}) {
  TrainingPlanOptions o;
  o.zooms = {kZ};
  o.empty_per_labelled = empty;
  return PlanTrainingWindows(detections, o, candidates, [](const WindowKey&) { return 1.0; });
}

const TrainingWindow* Find(const TrainingPlan& p, int x, int y) {
  for (const TrainingWindow& w : p.windows)
    if (w.key.x == x && w.key.y == y) return &w;
  return nullptr;
}

TEST(TrainingWindowsTest, RolesFollowTheReview) {
  EXPECT_EQ(RoleOf(At(1, "tyre", "recogniser", "confirmed", 0, 0, 1, 1)), TrainingRole::kLabel);
  EXPECT_EQ(RoleOf(At(1, "tyre", "recogniser", "rejected", 0, 0, 1, 1)), TrainingRole::kNegative);
  EXPECT_EQ(RoleOf(At(1, "tyre", "recogniser", "unconfirmed", 0, 0, 1, 1)), TrainingRole::kIgnored);
  EXPECT_EQ(RoleOf(At(1, "drum", "operator", "confirmed", 0, 0, 1, 1)), TrainingRole::kLabel);
  EXPECT_EQ(RoleOf(At(1, "drum", "operator", "confirmed", 0, 0, 1, 1, false)), TrainingRole::kPointIgnored);
  EXPECT_EQ(RoleOf(At(1, "drum", "stereo", "unconfirmed", 0, 0, 1, 1)), TrainingRole::kIgnored);
}

TEST(TrainingWindowsTest, ALabelIsInEveryWindowHoldingItsCentreClippedAndInWindowPixels) {
  // Centre in tile (1001, 2001): the four windows starting at 1000/1002 x 2000/2002 hold... only those whose
  // 3 tiles include 1001: x 1000 (1000-1002); y 2000. One window; a box near a shared tile is in four.
  const Detection shared = At(7, "tyre", "recogniser", "confirmed", kX + 2 * kT + 40, kY + 2 * kT + 50,
                              kX + 2 * kT + 140, kY + 2 * kT + 120);
  const TrainingPlan plan = Plan({shared});
  ASSERT_EQ(plan.windows.size(), 4u);
  EXPECT_EQ(plan.labelled, 4);
  const TrainingWindow* w = Find(plan, 1000, 2000);
  ASSERT_NE(w, nullptr);
  ASSERT_EQ(w->labels.size(), 1u);
  EXPECT_NEAR(w->labels[0].box_px[0], 2 * kT + 40, 1e-3);
  EXPECT_NEAR(w->labels[0].box_px[1], 2 * kT + 50, 1e-3);
  EXPECT_NEAR(w->labels[0].box_px[2], 2 * kT + 140, 1e-3);
  EXPECT_NEAR(w->labels[0].box_px[3], 2 * kT + 120, 1e-3);
  EXPECT_EQ(w->labels[0].source, "confirmed");
  const TrainingWindow* se = Find(plan, 1002, 2002);
  ASSERT_NE(se, nullptr);
  ASSERT_EQ(se->labels.size(), 1u);
  EXPECT_NEAR(se->labels[0].box_px[0], 40, 1e-3);
  EXPECT_EQ(YoloLabelText(se->labels, {"tyre"}, 768), "0 0.117188 0.110677 0.130208 0.091146\n");
}

TEST(TrainingWindowsTest, NegativesAreListedNotLabelledAndUnreviewedObjectsAreMasked) {
  const Detection rejected = At(1, "anchor", "recogniser", "rejected", kX + 300, kY + 300, kX + 360, kY + 340);
  const Detection unreviewed = At(2, "rock", "recogniser", "unconfirmed", kX + 100, kY + 100, kX + 130, kY + 140);
  const Detection drum = At(3, "drum", "operator", "confirmed", kX + 400, kY + 100, kX + 470, kY + 200);
  const TrainingPlan plan = Plan({rejected, unreviewed, drum});
  const TrainingWindow* w = Find(plan, 1000, 2000);
  ASSERT_NE(w, nullptr);
  ASSERT_EQ(w->labels.size(), 1u);
  EXPECT_EQ(w->labels[0].class_name, "drum");
  EXPECT_EQ(w->labels[0].source, "operator");
  ASSERT_EQ(w->negatives.size(), 1u);
  EXPECT_EQ(w->negatives[0].id, 1);
  ASSERT_EQ(w->masked_px.size(), 1u);
  EXPECT_TRUE(w->masked_px[0].contains({115, 120}));
  EXPECT_EQ(plan.ignored, 1);

  // Composed: grey under the mask, the map elsewhere.
  const TileReader white = [](const TileId&) -> std::optional<cv::Mat> {
    return cv::Mat(kT, kT, CV_8UC4, cv::Scalar(200, 200, 200, 255));
  };
  const cv::Mat bgr = ComposeTrainingWindow(*w, kT, white);
  ASSERT_EQ(bgr.cols, 768);
  EXPECT_EQ(bgr.at<cv::Vec3b>(120, 115), cv::Vec3b(114, 114, 114));
  EXPECT_EQ(bgr.at<cv::Vec3b>(320, 330), cv::Vec3b(200, 200, 200)) << "a rejected object stays visible";
}

TEST(TrainingWindowsTest, OverlapsAndPointMarksKeepWindowsOut) {
  // An unconfirmed box over a confirmed one: masking would cut the label, so no window.
  const Detection label = At(1, "tyre", "recogniser", "confirmed", kX + 300, kY + 300, kX + 380, kY + 380);
  const Detection over = At(2, "crate", "recogniser", "unconfirmed", kX + 370, kY + 370, kX + 420, kY + 420);
  TrainingPlan plan = Plan({label, over});
  EXPECT_EQ(plan.windows.size(), 0u);
  EXPECT_GT(plan.skipped_overlap, 0);
  // A point mark (no extent) in the window: out too.
  const Detection point = At(3, "net", "operator", "confirmed", kX + 600, kY + 600, kX + 600, kY + 600, false);
  plan = Plan({label, point});
  EXPECT_EQ(Find(plan, 1000, 2000), nullptr);
}

TEST(TrainingWindowsTest, ALabelLessThanHalfInsideIsMaskedAndEmptyWindowsAreSampled) {
  // A 200 px box centred 60 px left of the window x 1002's west edge: in window 1002 only 20 % is inside.
  const Detection pipe =
      At(1, "pipe", "recogniser", "confirmed", kX + 2 * kT - 160, kY + 300, kX + 2 * kT + 40, kY + 330);
  std::vector<WindowKey> candidates;
  for (int x = 990; x <= 1010; x += 2) candidates.push_back({kZ, x, 2000});
  const TrainingPlan plan = Plan({pipe}, 2, candidates);
  const TrainingWindow* w = Find(plan, 1000, 2000);
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->labels.size(), 1u);
  EXPECT_EQ(plan.labelled, 1) << "its centre lies in window 1000 only";
  EXPECT_EQ(plan.empty, 2);
  for (const TrainingWindow& e : plan.windows)
    if (e.labels.empty()) {
      EXPECT_TRUE(e.negatives.empty());
      EXPECT_NE(e.key.x, 1002) << "window 1002 touches the pipe: not an empty window";
    }
  const Detection across =
      At(2, "pipe", "recogniser", "confirmed", kX + 2 * kT + 80, kY + 300, kX + 2 * kT + 160, kY + 330);
  // Window 1002 holds this one's centre; the first pipe is 20 % inside it: masked there.
  const TrainingPlan both = Plan({pipe, across});
  const TrainingWindow* w2 = Find(both, 1002, 2000);
  ASSERT_NE(w2, nullptr);
  EXPECT_EQ(w2->labels.size(), 1u);
  EXPECT_EQ(w2->labels[0].id, 2);
  EXPECT_EQ(w2->masked_px.size(), 1u);
}

}  // namespace
}  // namespace seamap
