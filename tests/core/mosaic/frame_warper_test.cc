#include "core/mosaic/frame_warper.h"

#include <climits>

#include <gtest/gtest.h>

#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/geo/web_mercator.h"

namespace seamap {
namespace {

FrameWarper Warper(const CameraModel& cam, const LocalFrame& frame, double seam_band = 0, int zoom = 25,
                   int grid_step = 16) {
  WarpOptions o;
  o.seam_band = seam_band;
  o.grid_step = grid_step;
  return FrameWarper(cam, frame, zoom, 256, o);
}

CameraModel TestCamera() {
  CameraModel c = CameraFromFocalLength(8, 12.9, 320, 240);
  return c;
}

// Global pixel of a warped frame's pixel with the highest value in one channel.
cv::Point2d Brightest(const WarpedFrame& f) {
  cv::Point p;
  cv::minMaxLoc(f.pixels, nullptr, nullptr, nullptr, &p, f.weight > 0);
  return {f.x0 + p.x + 0.5, f.y0 + p.y + 0.5};
}

TEST(FrameWarper, OutlineCornersAreWhereTheGroundCornersProject) {
  // The outline maps the border through PROJ at the frame's centre only and
  // affinely around it: the corners stay within a thousandth of a pixel of
  // their exact projection, near the origin and kilometres from it, tilted,
  // and at a high latitude.
  const CameraModel cam = TestCamera();
  for (const LatLon origin : {LatLon{43.1, 131.9}, LatLon{71.0, -8.0}}) {
    LocalFrame frame(origin);
    const FrameWarper warper = Warper(cam, frame);
    for (const double away : {0.0, 5000.0}) {
      VehiclePose pose;
      pose.east_m = away;
      pose.north_m = -away;
      pose.altitude_m = 3.0;
      pose.heading_deg = 37;
      pose.pitch_deg = 20;
      pose.roll_deg = -15;
      const auto outline = warper.projection().Outline(pose);
      const auto ground = warper.projection().GroundCorners(pose);
      ASSERT_TRUE(outline && ground);
      for (int i = 0; i < 4; ++i) {
        const GlobalPixel exact = LatLonToPixel(frame.ToLatLon((*ground)[i]), 25, 256);
        EXPECT_NEAR(outline->corners[i].x, exact.x - 0.5, 1e-3) << origin.lat << " " << away << " corner " << i;
        EXPECT_NEAR(outline->corners[i].y, exact.y - 0.5, 1e-3) << origin.lat << " " << away << " corner " << i;
      }
    }
  }
}

TEST(FrameWarper, NadirFrameIsCentredOnTheVehicleAndNorthUp) {
  const LatLon origin{43.1, 131.9};
  LocalFrame frame(origin);
  CameraModel cam = TestCamera();
  const int zoom = 25;
  const FrameWarper warper = Warper(cam, frame, 0, zoom);
  VehiclePose pose;
  pose.altitude_m = 2.0;
  cv::Mat image(cam.height, cam.width, CV_8U, cv::Scalar(50));
  // A bright dot at the principal point, another in the top-left quadrant.
  cv::circle(image, {static_cast<int>(cam.cx + 0.5), static_cast<int>(cam.cy + 0.5)}, 2, 255, -1);
  auto warped = warper.Warp(image, pose);
  ASSERT_TRUE(warped);
  GlobalPixel expected = LatLonToPixel(origin, zoom, 256);
  cv::Point2d got = Brightest(*warped);
  EXPECT_NEAR(got.x, expected.x, 1.5);
  EXPECT_NEAR(got.y, expected.y, 1.5);

  // Size: footprint width / metres per pixel.
  const double mpp = MetersPerPixel(origin.lat, zoom, 256);
  EXPECT_NEAR(warped->pixels.cols, cam.width * pose.altitude_m / cam.fx / mpp, 2);
  EXPECT_NEAR(warped->pixels.rows, cam.height * pose.altitude_m / cam.fy / mpp, 2);

  // Image top is north: a dot near the top edge lands at smaller y.
  cv::Mat top(cam.height, cam.width, CV_8U, cv::Scalar(50));
  cv::circle(top, {cam.width / 2, 20}, 2, 255, -1);
  cv::Point2d top_px = Brightest(*warper.Warp(top, pose));
  EXPECT_LT(top_px.y, expected.y - 50);
  EXPECT_NEAR(top_px.x, expected.x, 2);
}

TEST(FrameWarper, HeadingEastTurnsImageTopEast) {
  LocalFrame frame({10, 20});
  CameraModel cam = TestCamera();
  const FrameWarper warper = Warper(cam, frame);
  VehiclePose pose;
  pose.altitude_m = 2.0;
  pose.heading_deg = 90;
  cv::Mat top(cam.height, cam.width, CV_8U, cv::Scalar(50));
  cv::circle(top, {cam.width / 2, 20}, 2, 255, -1);
  auto warped = warper.Warp(top, pose);
  ASSERT_TRUE(warped);
  GlobalPixel centre = LatLonToPixel({10, 20}, 25, 256);
  cv::Point2d p = Brightest(*warped);
  EXPECT_GT(p.x, centre.x + 50);
  EXPECT_NEAR(p.y, centre.y, 2);
}

TEST(FrameWarper, WeightIsHighestInTheCentreAndZeroOutside) {
  LocalFrame frame({10, 20});
  CameraModel cam = TestCamera();
  const FrameWarper warper = Warper(cam, frame);
  VehiclePose pose;
  pose.altitude_m = 2.0;
  pose.heading_deg = 30;  // rotated: bounding-box corners are outside the frame
  auto warped = warper.Warp(cv::Mat(cam.height, cam.width, CV_8U, cv::Scalar(80)), pose);
  ASSERT_TRUE(warped);
  const cv::Mat& weight = warped->weight;
  EXPECT_EQ(weight.at<uint8_t>(0, 0), 0);
  EXPECT_GT(weight.at<uint8_t>(weight.rows / 2, weight.cols / 2), 240);
}

}  // namespace
}  // namespace seamap

namespace seamap {
namespace {

int Covered(const WarpedFrame& f) {
  return cv::countNonZero(f.weight);
}

TEST(FrameWarper, HandsOverToCloserNeighboursWithAFeatheredSeam) {
  LocalFrame frame({43.1, 131.9});
  CameraModel cam = TestCamera();
  const FrameWarper all = Warper(cam, frame, 0.0);
  const FrameWarper banded = Warper(cam, frame, 0.5);
  VehiclePose pose;
  pose.altitude_m = 2.0;
  const double footprint_h = cam.height * pose.altitude_m / cam.fy;
  VehiclePose ahead = pose, behind = pose;
  ahead.north_m += footprint_h / 10;  // 10x overlap along track, as at 5 frames/s
  behind.north_m -= footprint_h / 10;
  cv::Mat image(cam.height, cam.width, CV_8U, cv::Scalar(80));
  auto full = all.Warp(image, pose, {behind, ahead});  // band 1: neighbours ignored
  auto own = banded.Warp(image, pose, {behind, ahead});
  ASSERT_TRUE(full && own);
  EXPECT_EQ(Covered(*full), Covered(*banded.Warp(image, pose)));
  // Keeps its own band between the midpoints plus half the way on to each
  // neighbour's centre: 1.5 spacings, 15 % of the frame.
  const double share = static_cast<double>(Covered(*own)) / Covered(*full);
  EXPECT_GT(share, 0.13);
  EXPECT_LT(share, 0.17);
  // The weight ramps down towards the neighbours: highest in the middle row.
  const int mid = own->weight.rows / 2, col = own->weight.cols / 2;
  EXPECT_GT(own->weight.at<uint8_t>(mid, col), 240);
  int first = -1;
  for (int y = 0; y < own->weight.rows && first < 0; ++y)
    if (own->weight.at<uint8_t>(y, col) > 0) first = y;
  ASSERT_GE(first, 0);
  EXPECT_LT(own->weight.at<uint8_t>(first, col), 60);
  // A row's runs start and end on painted pixels; a row without any has none.
  for (int y = 0; y < own->weight.rows; ++y) {
    const cv::Mat row = own->weight.row(y);
    const int first_run = own->run_offset[y], end_run = own->run_offset[y + 1];
    if (cv::countNonZero(row) == 0) {
      EXPECT_EQ(first_run, end_run);
      continue;
    }
    ASSERT_LT(first_run, end_run);
    EXPECT_GT(row.at<uint8_t>(own->runs[first_run][0]), 0);
    EXPECT_GT(row.at<uint8_t>(own->runs[end_run - 1][1] - 1), 0);
  }
}

// A frame between neighbours a tenth of a footprint ahead and behind,
// flying higher: wider than both, so the slivers along its sides, its whole
// length, are its own to paint.
struct WiderThanItsNeighbours {
  CameraModel cam = CameraFromFocalLength(8, 12.9, 160, 120);
  VehiclePose pose, behind, ahead;
  WiderThanItsNeighbours() {
    pose.altitude_m = 2.0;
    ahead = behind = pose;
    const double footprint_h = cam.height * pose.altitude_m / cam.fy;
    ahead.north_m += footprint_h / 10;
    behind.north_m -= footprint_h / 10;
    pose.altitude_m = 2.1;
  }
};

TEST(FrameWarper, RunsHoldEveryPaintedPixelAndSkipTheGaps) {
  // The frame paints a band plus the slivers along its sides that its
  // neighbours do not see: each row's runs cover every painted pixel, are
  // ordered, and leave the empty middle out.
  const WiderThanItsNeighbours wider;
  const CameraModel& cam = wider.cam;
  LocalFrame frame({43.1, 131.9});
  const FrameWarper banded = Warper(cam, frame, 0.5);
  auto own =
      banded.Warp(cv::Mat(cam.height, cam.width, CV_8U, cv::Scalar(80)), wider.pose, {wider.behind, wider.ahead});
  ASSERT_TRUE(own);
  ASSERT_EQ(own->run_offset.size(), static_cast<size_t>(own->weight.rows) + 1);
  int64_t in_runs = 0, split_rows = 0;
  for (int y = 0; y < own->weight.rows; ++y) {
    int previous_end = -1;
    for (int k = own->run_offset[y]; k < own->run_offset[y + 1]; ++k) {
      const auto& r = own->runs[k];
      EXPECT_LT(previous_end, r[0]);
      EXPECT_LT(r[0], r[1]);
      in_runs += cv::countNonZero(own->weight.row(y).colRange(r[0], r[1]));
      previous_end = r[1];
    }
    split_rows += own->run_offset[y + 1] - own->run_offset[y] > 1;
  }
  EXPECT_EQ(in_runs, cv::countNonZero(own->weight));
  EXPECT_GT(split_rows, 10);  // slivers apart from the band
  // PaintsAny, reading runs only, agrees with counting the weights.
  int empty = 0;
  for (int y = 0; y < own->weight.rows; y += 7)
    for (int x = 0; x < own->weight.cols; x += 9) {
      const cv::Rect roi(x, y, std::min(13, own->weight.cols - x), std::min(11, own->weight.rows - y));
      const bool any = cv::countNonZero(own->weight(roi)) > 0;
      EXPECT_EQ(PaintsAny(*own, roi), any) << roi;
      empty += !any;
    }
  EXPECT_GT(empty, 10);
}

TEST(FrameWarper, EveryPixelIsKeptByTheFrameThatSeesItBest) {
  // Three frames along a line with their neighbours: together they cover
  // what the full middle frame covers between the outer frames' centres.
  LocalFrame frame({43.1, 131.9});
  CameraModel cam = TestCamera();
  cam.distortion = {-0.2, 0.05, 0.001, -0.001, 0};
  const FrameWarper banded = Warper(cam, frame, 0.5);
  std::vector<VehiclePose> poses(5);
  for (int i = 0; i < 5; ++i) {
    poses[i].altitude_m = 2.0 + 0.05 * i;
    poses[i].north_m = 0.07 * i;
    poses[i].east_m = 0.01 * i;
    poses[i].heading_deg = 3.0 * i;
  }
  cv::Mat image(cam.height, cam.width, CV_8U, cv::Scalar(80));
  std::vector<WarpedFrame> warped;
  for (int i = 0; i < 5; ++i) {
    std::vector<VehiclePose> n;
    if (i > 0) n.push_back(poses[i - 1]);
    if (i < 4) n.push_back(poses[i + 1]);
    warped.push_back(*banded.Warp(image, poses[i], n));
  }
  // The middle frame's full footprint, between frames 1 and 3's centres.
  const WarpedFrame whole = *Warper(cam, frame).Warp(image, poses[2]);
  const GlobalPixel c1 = LatLonToPixel(frame.ToLatLon({poses[1].east_m, poses[1].north_m}), 25, 256);
  const GlobalPixel c3 = LatLonToPixel(frame.ToLatLon({poses[3].east_m, poses[3].north_m}), 25, 256);
  int checked = 0, holes = 0;
  for (int y = 0; y < whole.weight.rows; ++y) {
    const int64_t gy = whole.y0 + y;
    if (gy < c3.y + 2 || gy > c1.y - 2) continue;  // north is up: frame 3 has the smaller y
    for (int x = 2; x < whole.weight.cols - 2; ++x) {
      if (whole.weight.at<uint8_t>(y, x) < 20) continue;  // stay off the frame edge
      const int64_t gx = whole.x0 + x;
      bool painted = false;
      for (const auto& w : warped) {
        const int64_t fx = gx - w.x0, fy = gy - w.y0;
        if (fx >= 0 && fy >= 0 && fx < w.weight.cols && fy < w.weight.rows && w.weight.at<uint8_t>(fy, fx) > 0)
          painted = true;
      }
      ++checked;
      holes += !painted;
    }
  }
  EXPECT_GT(checked, 10000);
  EXPECT_EQ(holes, 0);
}

}  // namespace
}  // namespace seamap

namespace seamap {
namespace {

TEST(FrameWarper, InterpolatedMappingMatchesTheExactOne) {
  // The default grid against exact evaluation at every pixel, on a textured
  // frame seen with pitch, roll, heading and lens distortion.
  LocalFrame frame({43.1, 131.9});
  CameraModel cam = TestCamera();
  cam.distortion = {-0.25, 0.08, 0.001, -0.002, 0};
  VehiclePose pose;
  pose.altitude_m = 1.8;
  pose.heading_deg = 33;
  pose.pitch_deg = 8;
  pose.roll_deg = -6;
  cv::Mat image(cam.height, cam.width, CV_8U);
  cv::randu(image, 0, 255);
  cv::GaussianBlur(image, image, {0, 0}, 2.0);
  cv::normalize(image, image, 0, 255, cv::NORM_MINMAX);
  const FrameWarper gridded = Warper(cam, frame);
  const FrameWarper exact = Warper(cam, frame, 0, 25, 1);
  auto a = gridded.Warp(image, pose);
  auto b = exact.Warp(image, pose);
  ASSERT_TRUE(a && b);
  ASSERT_EQ(a->x0, b->x0);
  ASSERT_EQ(a->y0, b->y0);
  ASSERT_EQ(a->pixels.size(), b->pixels.size());
  // Where both paint (the edge may differ by a pixel), values agree to a
  // level or two: the texture changes by up to ~25 levels per pixel, so the
  // sampling positions agree to well under a tenth of a pixel.
  cv::Mat both = (a->weight > 0) & (b->weight > 0);
  cv::Mat diff;
  cv::absdiff(a->pixels, b->pixels, diff);
  double max_diff = 0;
  cv::minMaxLoc(diff, nullptr, &max_diff, nullptr, nullptr, both);
  EXPECT_LE(max_diff, 2);
  EXPECT_LT(cv::mean(diff, both)[0], 0.3);
  // Coverage agrees but for the edge pixels.
  EXPECT_NEAR(cv::countNonZero(a->weight), cv::countNonZero(b->weight), 0.01 * cv::countNonZero(b->weight));
}

}  // namespace
}  // namespace seamap

namespace seamap {
namespace {

TEST(FrameWarper, AsksOnlyForTheRawRowsItSamples) {
  // A frame between neighbours paints a band: it asks for the raw rows of
  // that band only (a JPEG kept compressed decodes just those), and what it
  // paints equals the same warp of the whole image.
  const WiderThanItsNeighbours wider;
  const CameraModel& cam = wider.cam;
  LocalFrame frame({43.1, 131.9});
  const FrameWarper banded = Warper(cam, frame, 0.5);
  cv::Mat image(cam.height, cam.width, CV_8U);
  cv::randu(image, 0, 256);
  cv::Mat band_only = cv::Mat::zeros(image.size(), image.type());
  int first_asked = INT_MAX, last_asked = -1;
  const FrameWarper::RowSource rows = [&](int first, int last) -> const cv::Mat& {
    first_asked = std::min(first_asked, first);
    last_asked = std::max(last_asked, last);
    const int a = std::max(first, 0), b = std::min(last, image.rows - 1);
    image.rowRange(a, b + 1).copyTo(band_only.rowRange(a, b + 1));
    return band_only;
  };
  const auto from_rows = banded.Warp(rows, wider.pose, {wider.behind, wider.ahead});
  const auto from_image = banded.Warp(image, wider.pose, {wider.behind, wider.ahead});
  ASSERT_TRUE(from_rows && from_image);
  // The wider frame's own side slivers run its whole length, so it needs
  // rows from near the top to near the bottom, but not every row.
  EXPECT_GE(first_asked, -1);
  EXPECT_LE(last_asked, cam.height);
  EXPECT_EQ(cv::norm(from_rows->pixels, from_image->pixels, cv::NORM_INF), 0);
  EXPECT_EQ(cv::norm(from_rows->weight, from_image->weight, cv::NORM_INF), 0);
  // A frame narrower than its neighbours (flying lower) leaves them its
  // sides too: it asks for its band's rows only.
  first_asked = INT_MAX;
  last_asked = -1;
  VehiclePose lower = wider.pose;
  lower.altitude_m = 1.9;
  ASSERT_TRUE(banded.Warp(rows, lower, {wider.behind, wider.ahead}));
  EXPECT_LT(last_asked - first_asked, cam.height / 3);
}

}  // namespace
}  // namespace seamap
