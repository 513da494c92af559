#include "core/mosaic/frame_tail.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <opencv2/imgcodecs.hpp>

#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

TEST(FrameTail, DecodedLaterTheTailIsSampledAsFromTheWholeFrame) {
  // A JPEG frame warped by rows with a tail, then its tail decoded on its
  // own: the same values as sampling the fully decoded frame, and the rows
  // are released again (only the compressed frame stays).
  testing::TempDir dir;
  CameraModel cam = CameraFromFocalLength(8, 12.9, 160, 120);
  cv::Mat texture(cam.height, cam.width, CV_8UC3);
  cv::randu(texture, 0, 256);
  const std::string path = (dir / "frame.jpg").string();
  cv::imwrite(path, texture, {cv::IMWRITE_JPEG_QUALITY, 95});
  for (int channels : {1, 3}) {
    std::string problem;
    auto image = FrameImage::Read(path, channels, 65535, &problem);
    ASSERT_TRUE(image) << problem;
    ASSERT_TRUE(image->DecodesByRows());
    const size_t compressed = image->Bytes();

    LocalFrame frame({43.1, 131.9});
    FrameWarper warper(cam, frame, 25, 256, channels, 1.0, 0.5);
    VehiclePose pose, ahead, behind;  // the frame wider than its neighbours: slivers down both sides
    pose.altitude_m = 2.1;
    ahead.altitude_m = behind.altitude_m = 2.0;
    ahead.north_m = 0.03;
    behind.north_m = -0.03;
    std::vector<TailPixel> tail;
    ASSERT_TRUE(
        warper.Warp([&](int a, int b) -> const cv::Mat& { return image->Rows(a, b); }, pose, {behind, ahead}, &tail));
    ASSERT_FALSE(tail.empty());
    // Upper and lower tails, so decoding skips the rows between them.
    const auto [lowest, highest] =
        std::minmax_element(tail.begin(), tail.end(), [](const TailPixel& a, const TailPixel& b) { return a.v < b.v; });
    ASSERT_LT(lowest->v, cam.height / 3);
    ASSERT_GT(highest->v, 2 * cam.height / 3);
    image->ReleasePixels();
    EXPECT_EQ(image->Bytes(), compressed);

    const WarpedFrame later = DecodeTail(*image, tail);
    EXPECT_EQ(image->Bytes(), compressed) << "decoded rows kept";
    const WarpedFrame reference = SampleTail(tail, image->Full());
    ASSERT_EQ(later.pixels.type(), reference.pixels.type());
    EXPECT_EQ(later.x0, reference.x0);
    EXPECT_EQ(later.y0, reference.y0);
    EXPECT_EQ(cv::norm(later.pixels, reference.pixels, cv::NORM_INF), 0) << channels << " channels";
    EXPECT_EQ(cv::norm(later.weight, reference.weight, cv::NORM_INF), 0);
    EXPECT_EQ(cv::countNonZero(later.weight), static_cast<int>(tail.size()));
  }
}

TEST(FrameTail, NoPixelsMakeAnEmptyFrame) {
  const WarpedFrame empty = SampleTail({}, cv::Mat(4, 4, CV_8UC3, cv::Scalar::all(9)));
  EXPECT_EQ(cv::countNonZero(empty.weight), 0);
  EXPECT_EQ(empty.pixels.type(), CV_8UC3);
  EXPECT_FALSE(PaintsAny(empty, cv::Rect(0, 0, 1, 1)));
}

}  // namespace
}  // namespace seamap
