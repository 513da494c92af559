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

}  // namespace
}  // namespace seamap
