#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "core/mosaic/overview_pyramid.h"

namespace seamap {
namespace {

TEST(ReduceTile2x, AveragesOpaqueBlocks) {
  cv::Mat t(4, 4, CV_8UC2, cv::Scalar(0, 255));
  t.at<cv::Vec2b>(0, 0)[0] = 10;
  t.at<cv::Vec2b>(0, 1)[0] = 20;
  t.at<cv::Vec2b>(1, 0)[0] = 30;
  t.at<cv::Vec2b>(1, 1)[0] = 41;
  cv::Mat r = ReduceTile2x(t);
  ASSERT_EQ(r.size(), cv::Size(2, 2));
  EXPECT_EQ(r.at<cv::Vec2b>(0, 0), cv::Vec2b(25, 255));  // 101/4 rounded
  EXPECT_EQ(r.at<cv::Vec2b>(1, 1), cv::Vec2b(0, 255));
}

TEST(ReduceTile2x, TransparentPixelsDoNotDarkenTheEdge) {
  cv::Mat t(2, 2, CV_8UC2, cv::Scalar(0, 0));
  t.at<cv::Vec2b>(0, 0) = {200, 255};
  cv::Mat r = ReduceTile2x(t);
  EXPECT_EQ(r.at<cv::Vec2b>(0, 0), cv::Vec2b(200, 64));  // colour kept, quarter coverage
}

TEST(ReduceTile2x, ColourKeepsChannels) {
  cv::Mat t(2, 2, CV_8UC4, cv::Scalar(1, 2, 3, 255));
  EXPECT_EQ(ReduceTile2x(t).at<cv::Vec4b>(0, 0), cv::Vec4b(1, 2, 3, 255));
}

// Every output pixel is the alpha-weighted mean of its four, rounded, whether
// all four are opaque (the shortcut) or not.
TEST(ReduceTile2x, EveryPixelIsTheRoundedAlphaWeightedMean) {
  cv::RNG rng(7);
  for (int ch : {2, 4}) {
    cv::Mat t(64, 64, CV_8UC(ch));
    rng.fill(t, cv::RNG::UNIFORM, 0, 256);
    for (int y = 0; y < t.rows; ++y)
      for (int x = 0; x < t.cols; ++x) {
        const int pick = rng.uniform(0, 4);  // opaque blocks are common, so are partial ones
        uint8_t& a = t.ptr<uint8_t>(y)[x * ch + ch - 1];
        a = pick == 0 ? 0 : pick == 3 ? a : 255;
        if ((y / 2 + x / 2) % 3 == 0) a = 255;  // whole blocks opaque
      }
    const cv::Mat r = ReduceTile2x(t);
    for (int y = 0; y < r.rows; ++y)
      for (int x = 0; x < r.cols; ++x) {
        int alpha = 0, sum[3] = {0, 0, 0};
        for (int k = 0; k < 4; ++k) {
          const uint8_t* p = t.ptr<uint8_t>(2 * y + k / 2) + (2 * x + k % 2) * ch;
          alpha += p[ch - 1];
          for (int c = 0; c + 1 < ch; ++c) sum[c] += p[c] * p[ch - 1];
        }
        const uint8_t* d = r.ptr<uint8_t>(y) + x * ch;
        if (alpha == 0) {
          for (int c = 0; c < ch; ++c) EXPECT_EQ(d[c], 0);
          continue;
        }
        for (int c = 0; c + 1 < ch; ++c) ASSERT_EQ(d[c], (sum[c] + alpha / 2) / alpha) << "at " << x << "," << y;
        ASSERT_EQ(d[ch - 1], (alpha + 2) / 4);
      }
  }
}

}  // namespace
}  // namespace seamap
