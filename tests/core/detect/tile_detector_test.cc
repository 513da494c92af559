#include "core/detect/tile_detector.h"

#include <gtest/gtest.h>

namespace seamap {
namespace {

const std::string kFixtures = std::string(SEAMAP_SOURCE_DIR) + "/tests/fixtures/";

TEST(ComposeWindow, MissingAndTransparentPixelsAreGreyAndGrayIsReplicated) {
  // Only the window's centre tile exists: gray 200, its left half transparent.
  cv::Mat tile(256, 256, CV_8UC2, cv::Scalar(200, 255));
  tile(cv::Rect(0, 0, 128, 256)).setTo(cv::Scalar(200, 0));
  tile.at<cv::Vec2b>(10, 200) = {0, 128};  // half-transparent black
  const TileReader read = [&](const TileId& id) -> std::optional<cv::Mat> {
    if (id.x == 5 && id.y == 9) return tile;
    return std::nullopt;
  };
  double painted = 0;
  const cv::Mat w = ComposeWindow({20, 4, 8}, 256, read, &painted);
  ASSERT_EQ(w.size(), cv::Size(768, 768));
  EXPECT_EQ(w.type(), CV_8UC3);
  EXPECT_EQ(w.at<cv::Vec3b>(0, 0), cv::Vec3b(114, 114, 114));
  EXPECT_EQ(w.at<cv::Vec3b>(256 + 5, 256 + 5), cv::Vec3b(114, 114, 114));
  EXPECT_EQ(w.at<cv::Vec3b>(256 + 5, 256 + 150), cv::Vec3b(200, 200, 200));
  EXPECT_EQ(w.at<cv::Vec3b>(256 + 10, 256 + 200), cv::Vec3b(57, 57, 57));  // 114 * 127 / 255
  EXPECT_NEAR(painted, 128.0 * 256 / (768.0 * 768), 1e-9);
}

TEST(TileDetector, SkipsEmptyWindowsAndPlacesBoxesInGlobalPixels) {
  auto info = YoloModel::Inspect(kFixtures + "yolo_v8_fixture.onnx", "");
  TileDetector detector(info, 256, 0.4f);
  const TileReader none = [](const TileId&) -> std::optional<cv::Mat> { return std::nullopt; };
  EXPECT_TRUE(detector.Search({20, 4, 8}, none).skipped);
  const cv::Mat opaque(256, 256, CV_8UC4, cv::Scalar(90, 90, 90, 255));
  const TileReader all = [&](const TileId&) -> std::optional<cv::Mat> { return opaque; };
  const WindowSearch s = detector.Search({20, 4, 8}, all);
  ASSERT_FALSE(s.skipped);
  ASSERT_EQ(s.found.size(), 2u);
  // The fixture's class-0 box: 38..50 input px of 64 -> 456..600 window px (scale 1/12).
  EXPECT_NEAR(s.found[0].box.x0, 4 * 256 + 456, 1e-2);
  EXPECT_NEAR(s.found[0].box.y0, 8 * 256 + 34 * 12, 1e-2);
  EXPECT_FALSE(s.found[0].truncated);
}

}  // namespace
}  // namespace seamap
