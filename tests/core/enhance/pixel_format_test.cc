#include "core/enhance/pixel_format.h"

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace seamap {
namespace {

TEST(PixelFormat, AcceptsGrayAndBgrIn8And16Bit) {
  for (int type : {CV_8UC1, CV_8UC3, CV_16UC1, CV_16UC3})
    EXPECT_NO_THROW(RequireSupportedImage(cv::Mat(4, 4, type, cv::Scalar::all(1)), "op"));
}

TEST(PixelFormat, RejectsFloatAndFourChannelsSayingWhatWasExpected) {
  for (int type : {CV_32FC1, CV_8UC4, CV_8UC2, CV_64FC3}) {
    try {
      RequireSupportedImage(cv::Mat(4, 4, type, cv::Scalar::all(0)), "clahe");
      FAIL() << "accepted " << cv::typeToString(type);
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "clahe");
      EXPECT_NE(std::string(e.what()).find("CV_8UC1, CV_8UC3, CV_16UC1, CV_16UC3"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(cv::typeToString(type)), std::string::npos) << e.what();
    }
  }
}

TEST(PixelFormat, RejectsEmptyImage) {
  EXPECT_THROW(RequireSupportedImage(cv::Mat(), "gamma"), InputError);
}

TEST(PixelFormat, UnitFloatRoundTripsBothDepths) {
  cv::Mat a8(2, 2, CV_8UC3, cv::Scalar(0, 128, 255));
  cv::Mat unit = ToUnitFloat(a8);
  EXPECT_NEAR(unit.at<cv::Vec3f>(0, 0)[2], 1.0f, 1e-6);
  EXPECT_EQ(cv::norm(FromUnitFloat(unit, a8.type()), a8, cv::NORM_INF), 0);
  cv::Mat a16(2, 2, CV_16UC1, cv::Scalar(65535));
  EXPECT_NEAR(ToUnitFloat(a16).at<float>(0, 0), 1.0f, 1e-6);
  EXPECT_EQ(ToGray8(a16).at<uchar>(1, 1), 255);
}

}  // namespace
}  // namespace seamap
