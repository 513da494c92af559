#include "core/mosaic/survey_channels.h"

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;

// Frames named f0.png.. : `colour[i]` says whether frame i is a colour file.
std::vector<FrameSpec> Survey(const TempDir& dir, const std::vector<bool>& colour) {
  std::vector<FrameSpec> frames;
  for (size_t i = 0; i < colour.size(); ++i) {
    FrameSpec f;
    f.index = static_cast<int>(i);
    f.image = "f" + std::to_string(i) + ".png";
    f.image_path = (dir / f.image).string();
    // A one-colour frame (all red) or a gray one with texture.
    cv::Mat m = colour[i] ? cv::Mat(40, 60, CV_8UC3, cv::Scalar(0, 0, 255)) : cv::Mat(40, 60, CV_8UC1);
    if (!colour[i]) cv::randu(m, 0, 255);
    EXPECT_TRUE(cv::imwrite(f.image_path, m));
    frames.push_back(f);
  }
  return frames;
}

TEST(SurveyChannels, AOneColourFirstFrameDoesNotMakeAGraySurveyColour) {
  TempDir dir;
  std::vector<bool> colour(12, false);
  colour[0] = true;
  const SurveyChannels c = DecideChannels(Survey(dir, colour), kDefaultMaxImagePixels);
  EXPECT_EQ(c.channels, 1);
  EXPECT_EQ(c.gray, 11);
  EXPECT_EQ(c.colour, 1);
  EXPECT_NE(c.warning.find("f0.png"), std::string::npos) << c.warning;
  EXPECT_NE(c.warning.find("the map is gray"), std::string::npos) << c.warning;
}

TEST(SurveyChannels, AGrayFirstFrameDoesNotMakeAColourSurveyGray) {
  TempDir dir;
  std::vector<bool> colour(12, true);
  colour[0] = false;
  const SurveyChannels c = DecideChannels(Survey(dir, colour), kDefaultMaxImagePixels);
  EXPECT_EQ(c.channels, 3);
  EXPECT_NE(c.warning.find("the map is colour"), std::string::npos) << c.warning;
}

TEST(SurveyChannels, UniformSurveysGiveNoWarningAndBrokenFramesDoNotCount) {
  TempDir dir;
  auto frames = Survey(dir, std::vector<bool>(5, true));
  testing::WriteFile(frames[1].image_path, "not an image");
  FrameSpec missing = frames[0];
  missing.image_path = (dir / "none.png").string();
  frames.insert(frames.begin(), missing);
  const SurveyChannels c = DecideChannels(frames, kDefaultMaxImagePixels);
  EXPECT_EQ(c.channels, 3);
  EXPECT_EQ(c.colour, 4);
  EXPECT_EQ(c.gray, 0);
  EXPECT_TRUE(c.warning.empty()) << c.warning;
  EXPECT_EQ(DecideChannels({}, kDefaultMaxImagePixels).channels, 1);
}

TEST(SurveyChannels, SamplesSpreadOverALongSurvey) {
  TempDir dir;
  // 200 frames, the first 40 colour: the sample of 16 sees mostly gray.
  std::vector<bool> colour(200, false);
  for (int i = 0; i < 40; ++i) colour[i] = true;
  const SurveyChannels c = DecideChannels(Survey(dir, colour), kDefaultMaxImagePixels, 16);
  EXPECT_EQ(c.gray + c.colour, 16);
  EXPECT_EQ(c.channels, 1);
  EXPECT_GE(c.colour, 2);
  EXPECT_LE(c.colour, 5);
}

}  // namespace
}  // namespace seamap
