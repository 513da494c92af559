#include "core/nav/frame_list.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "core/nav/nav_reader.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using ::seamap::testing::TempDir;
using ::seamap::testing::WriteFile;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

class FrameListTest : public ::testing::Test {
 protected:
  NavTable ReadNav(const std::string& text) {
    nav_path_ = WriteFile(dir_ / "nav.csv", text).string();
    return ReadNavigation(nav_path_, {});
  }
  std::string Write(const std::string& name, const std::string& text) { return WriteFile(dir_ / name, text).string(); }
  TempDir dir_;
  std::string nav_path_;
};

TEST_F(FrameListTest, NamedImagesAreFramesInTimeOrderWithoutDuplicates) {
  const NavTable nav = ReadNav(
      "image,time,lat,lon,alt\n"
      "b.jpg,2,43,131,2\n"
      ",2.5,43,131,2\n"  // a navigation sample between photos
      "a.jpg,1,43,131,3\n"
      "b.jpg,3,43,131,2\n");
  const FrameList list = MatchFrames(nav, "photos", std::nullopt);
  ASSERT_EQ(list.frames.size(), 2u);
  EXPECT_EQ(list.frames[0].image, "a.jpg");
  EXPECT_EQ(list.frames[0].index, 0);
  EXPECT_EQ(list.frames[0].nav_line, 4);
  EXPECT_EQ(list.frames[0].image_path, (std::filesystem::path("photos") / "a.jpg").string());
  EXPECT_DOUBLE_EQ(list.frames[0].pose.altitude_m, 3);
  EXPECT_EQ(list.frames[1].image, "b.jpg");
  EXPECT_EQ(list.frames[1].index, 1);
  ASSERT_EQ(list.rejected.size(), 1u);
  EXPECT_EQ(list.rejected[0].line, 5);
  EXPECT_EQ(list.rejected[0].field, "image");
  EXPECT_TRUE(
      Contains(list.rejected[0].Message(), nav_path_ + ":5: field 'image': duplicate image 'b.jpg' (first at line 2)"))
      << list.rejected[0].Message();
}

TEST_F(FrameListTest, WithoutTimesFileOrderIsKept) {
  const NavTable nav = ReadNav("image,lat,lon,alt\nz.jpg,43,131,2\na.jpg,43,131,2\n");
  const FrameList list = MatchFrames(nav, "/data", std::nullopt);
  ASSERT_EQ(list.frames.size(), 2u);
  EXPECT_EQ(list.frames[0].image, "z.jpg");
  EXPECT_FALSE(list.frames[0].time_s);
  EXPECT_EQ(list.frames[1].index, 1);
}

TEST_F(FrameListTest, ImageTimesAreInterpolatedAndOutOfSpanRejected) {
  NavReadOptions options;
  options.origin = LatLon{43, 131};
  nav_path_ = Write("nav.csv", "t,x,y,alt,heading\n0,0,0,2,350\n10,10,20,4,10\n20,20,20,4,10\n");
  const NavTable nav = ReadNavigation(nav_path_, options);
  ASSERT_FALSE(nav.has_images);
  const std::string times = Write("times.csv",
                                  "photo;seconds\n"
                                  "c.jpg;15\n"
                                  "a.jpg;5\n"
                                  "early.jpg;-1\n"
                                  "late.jpg;20,5\n"
                                  "bad.jpg;NaN\n"
                                  "a.jpg;6\n"
                                  "short.jpg\n");
  const FrameList list = MatchFrames(nav, "img", times);
  ASSERT_EQ(list.frames.size(), 2u);
  const FrameSpec& a = list.frames[0];
  EXPECT_EQ(a.image, "a.jpg");
  EXPECT_EQ(a.index, 0);
  EXPECT_EQ(a.nav_line, 0);
  EXPECT_DOUBLE_EQ(*a.time_s, 5);
  EXPECT_DOUBLE_EQ(a.pose.east_m, 5);
  EXPECT_DOUBLE_EQ(a.pose.north_m, 10);
  EXPECT_DOUBLE_EQ(a.pose.altitude_m, 3);
  EXPECT_NEAR(a.pose.heading_deg, 0, 1e-9);
  EXPECT_EQ(list.frames[1].image, "c.jpg");
  EXPECT_DOUBLE_EQ(list.frames[1].pose.east_m, 15);

  ASSERT_EQ(list.rejected.size(), 5u);
  for (const Rejection& r : list.rejected) EXPECT_EQ(r.file, times);
  EXPECT_EQ(list.rejected[0].line, 4);
  EXPECT_EQ(list.rejected[0].field, "time_s");
  EXPECT_TRUE(Contains(list.rejected[0].reason, "time_s -1 is outside the navigation's time span [0, 20] s"))
      << list.rejected[0].reason;
  EXPECT_EQ(list.rejected[1].line, 5);  // 20,5 with a decimal comma
  EXPECT_EQ(list.rejected[2].line, 6);
  EXPECT_TRUE(Contains(list.rejected[2].reason, "NaN")) << list.rejected[2].reason;
  EXPECT_EQ(list.rejected[3].line, 7);
  EXPECT_TRUE(Contains(list.rejected[3].reason, "duplicate")) << list.rejected[3].reason;
  EXPECT_EQ(list.rejected[4].line, 8);
  EXPECT_EQ(list.rejected[4].field, "time_s");
}

TEST_F(FrameListTest, ImageTimesFileProblemsAreFatal) {
  const NavTable nav = ReadNav("time,lat,lon,alt\n0,43,131,2\n1,43,131,2\n");
  const std::string no_time = Write("times.csv", "image,when\na.jpg,1\n");
  try {
    MatchFrames(nav, "img", no_time);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), no_time);
    EXPECT_EQ(e.field(), "time_s");
    EXPECT_EQ(e.line(), 1);
  }
  EXPECT_THROW(MatchFrames(nav, "img", (dir_ / "missing.csv").string()), InputError);
}

TEST_F(FrameListTest, NoImagesAndNoImageTimesIsFatal) {
  const NavTable nav = ReadNav("time,lat,lon,alt\n0,43,131,2\n");
  try {
    MatchFrames(nav, "img", std::nullopt);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), nav_path_);
    EXPECT_EQ(e.field(), "image");
    EXPECT_TRUE(Contains(e.what(), "--image-times")) << e.what();
  }
}

}  // namespace
}  // namespace seamap
