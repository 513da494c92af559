#include "core/camera/camera_model.h"

#include <sys/stat.h>

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <opencv2/core.hpp>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::TempDir;
using testing::WriteFile;

// Runs `load` and returns the InputError it throws (fails the test if none).
template <typename F>
InputError ExpectInputError(F load) {
  try {
    load();
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "expected InputError";
  return InputError("", 0, "", "");
}

TEST(CameraModelTest, LoadsOurJsonWithDistortionAndMount) {
  TempDir dir;
  const auto path = WriteFile(dir / "cam.json", R"({
    "width": 696, "height": 520, "fx": 620.5, "fy": 621.5, "cx": 347.0, "cy": 259.0,
    "distortion": [-0.2, 0.05, 0.001, -0.002, 0.01],
    "mount": {"roll_deg": 1, "pitch_deg": 2, "yaw_deg": 3, "offset_m": [0.5, -0.1, 0.2]}
  })");
  const CameraModel c = LoadCamera(path.string());
  EXPECT_EQ(c.width, 696);
  EXPECT_EQ(c.height, 520);
  EXPECT_DOUBLE_EQ(c.fx, 620.5);
  EXPECT_DOUBLE_EQ(c.fy, 621.5);
  EXPECT_DOUBLE_EQ(c.cx, 347.0);
  EXPECT_DOUBLE_EQ(c.cy, 259.0);
  EXPECT_DOUBLE_EQ(c.distortion[0], -0.2);
  EXPECT_DOUBLE_EQ(c.distortion[4], 0.01);
  EXPECT_TRUE(c.HasDistortion());
  EXPECT_EQ(c.mount_rpy_deg, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(c.mount_offset_m, Eigen::Vector3d(0.5, -0.1, 0.2));
  const cv::Mat d = c.DistortionCoeffs();
  EXPECT_EQ(d.rows, 1);
  EXPECT_EQ(d.cols, 5);
  EXPECT_EQ(d.type(), CV_64F);
  EXPECT_DOUBLE_EQ(d.at<double>(0, 3), -0.002);
}

TEST(CameraModelTest, JsonDistortionLengthsArePaddedOrTruncated) {
  TempDir dir;
  const auto four = WriteFile(dir / "four.json", R"({"width": 10, "height": 8, "fx": 5, "fy": 5,
    "cx": 5, "cy": 4, "distortion": [0.1, 0.2, 0.3, 0.4]})");
  CameraModel c = LoadCamera(four.string());
  EXPECT_EQ(c.distortion, (std::array<double, 5>{0.1, 0.2, 0.3, 0.4, 0}));

  const auto eight = WriteFile(dir / "eight.json", R"({"width": 10, "height": 8, "fx": 5, "fy": 5,
    "cx": 5, "cy": 4, "distortion": [0.1, 0.2, 0.3, 0.4, 0.5, 0, 0, 0]})");
  c = LoadCamera(eight.string());
  EXPECT_EQ(c.distortion, (std::array<double, 5>{0.1, 0.2, 0.3, 0.4, 0.5}));

  const auto none = WriteFile(dir / "none.json", R"({"width": 10, "height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": 4})");
  c = LoadCamera(none.string());
  EXPECT_FALSE(c.HasDistortion());
  EXPECT_EQ(c.mount_rpy_deg, Eigen::Vector3d::Zero());
}

TEST(CameraModelTest, UnsupportedDistortionTermsAreRejected) {
  TempDir dir;
  const auto rational = WriteFile(dir / "rational.json", R"({"width": 10, "height": 8, "fx": 5,
    "fy": 5, "cx": 5, "cy": 4, "distortion": [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0, 0]})");
  InputError e = ExpectInputError([&] { LoadCamera(rational.string()); });
  EXPECT_EQ(e.field(), "distortion");
  EXPECT_NE(std::string(e.what()).find("rational.json"), std::string::npos);

  const auto six = WriteFile(dir / "six.json", R"({"width": 10, "height": 8, "fx": 5,
    "fy": 5, "cx": 5, "cy": 4, "distortion": [0, 0, 0, 0, 0, 0]})");
  e = ExpectInputError([&] { LoadCamera(six.string()); });
  EXPECT_EQ(e.field(), "distortion");
}

TEST(CameraModelTest, FocalShortcutMatchesSeedPaperNumbers) {
  const CameraModel c = CameraFromFocalLength(8.0, 12.9, 696, 520);
  EXPECT_NEAR(c.fx, 620.155, 1e-3);
  EXPECT_DOUBLE_EQ(c.fx, c.fy);
  EXPECT_DOUBLE_EQ(c.cx, 347.5);
  EXPECT_DOUBLE_EQ(c.cy, 259.5);
  EXPECT_FALSE(c.HasDistortion());
  EXPECT_EQ(ExpectInputError([] { CameraFromFocalLength(0, 12.9, 10, 10); }).field(), "focal_mm");
}

TEST(CameraModelTest, LoadsFocalShortcutJson) {
  TempDir dir;
  const auto path =
      WriteFile(dir / "seed.json", R"({"width": 696, "height": 520, "focal_mm": 8, "pixel_pitch_um": 12.9})");
  const CameraModel c = LoadCamera(path.string());
  EXPECT_NEAR(c.fx, 620.155, 1e-3);
  EXPECT_NEAR(c.fy, 620.155, 1e-3);
  EXPECT_DOUBLE_EQ(c.cx, 347.5);
  EXPECT_DOUBLE_EQ(c.cy, 259.5);

  const auto with_centre = WriteFile(dir / "seed2.json", R"({"width": 696, "height": 520,
    "focal_mm": 8, "pixel_pitch_um": 12.9, "cx": 340, "cy": 250})");
  const CameraModel c2 = LoadCamera(with_centre.string());
  EXPECT_DOUBLE_EQ(c2.cx, 340);
  EXPECT_DOUBLE_EQ(c2.cy, 250);

  const auto no_pitch = WriteFile(dir / "seed3.json", R"({"width": 696, "height": 520, "focal_mm": 8})");
  EXPECT_EQ(ExpectInputError([&] { LoadCamera(no_pitch.string()); }).field(), "pixel_pitch_um");
}

TEST(CameraModelTest, SaveThenLoadRoundTrips) {
  TempDir dir;
  CameraModel c;
  c.width = 1024;
  c.height = 768;
  c.fx = 800.25;
  c.fy = 799.75;
  c.cx = 510.5;
  c.cy = 380.125;
  c.distortion = {-0.1, 0.02, 0.0005, -0.0003, 0.001};
  c.mount_rpy_deg = {0.5, -1.5, 90};
  c.mount_offset_m = {1.2, 0, 0.3};
  const std::string path = (dir / "saved.json").string();
  SaveCameraJson(c, path);
  const CameraModel back = LoadCamera(path);
  EXPECT_EQ(back.width, c.width);
  EXPECT_EQ(back.height, c.height);
  EXPECT_DOUBLE_EQ(back.fx, c.fx);
  EXPECT_DOUBLE_EQ(back.fy, c.fy);
  EXPECT_DOUBLE_EQ(back.cx, c.cx);
  EXPECT_DOUBLE_EQ(back.cy, c.cy);
  EXPECT_EQ(back.distortion, c.distortion);
  EXPECT_EQ(back.mount_rpy_deg, c.mount_rpy_deg);
  EXPECT_EQ(back.mount_offset_m, c.mount_offset_m);
}

// Writes a calibration the way OpenCV's calibration sample does.
void WriteOpenCvCalibration(const std::string& path, const cv::Mat& dist) {
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  fs << "image_width" << 1280 << "image_height" << 960;
  fs << "camera_matrix" << cv::Mat(cv::Matx33d(1000.5, 0, 640.25, 0, 1001.5, 480.75, 0, 0, 1));
  fs << "distortion_coefficients" << dist;
}

TEST(CameraModelTest, LoadsOpenCvYamlAndXml) {
  TempDir dir;
  const cv::Mat row = (cv::Mat_<double>(1, 5) << -0.25, 0.1, 0.001, 0.002, -0.03);
  for (const std::string name : {"calib.yaml", "calib.yml", "calib.xml"}) {
    const std::string path = (dir / name).string();
    WriteOpenCvCalibration(path, row);
    const CameraModel c = LoadCamera(path);
    EXPECT_EQ(c.width, 1280) << name;
    EXPECT_EQ(c.height, 960) << name;
    EXPECT_DOUBLE_EQ(c.fx, 1000.5) << name;
    EXPECT_DOUBLE_EQ(c.fy, 1001.5) << name;
    EXPECT_DOUBLE_EQ(c.cx, 640.25) << name;
    EXPECT_DOUBLE_EQ(c.cy, 480.75) << name;
    EXPECT_EQ(c.distortion, (std::array<double, 5>{-0.25, 0.1, 0.001, 0.002, -0.03})) << name;
  }
  // Column vector and 4/8-element variants.
  const std::string col = (dir / "col.yaml").string();
  WriteOpenCvCalibration(col, cv::Mat(row.t()));
  EXPECT_DOUBLE_EQ(LoadCamera(col).distortion[4], -0.03);
  const std::string four = (dir / "four.yaml").string();
  WriteOpenCvCalibration(four, (cv::Mat_<double>(1, 4) << 0.1, 0.2, 0.3, 0.4));
  EXPECT_EQ(LoadCamera(four).distortion, (std::array<double, 5>{0.1, 0.2, 0.3, 0.4, 0}));
  const std::string eight = (dir / "eight.yaml").string();
  WriteOpenCvCalibration(eight, (cv::Mat_<double>(8, 1) << 0.1, 0.2, 0.3, 0.4, 0.5, 0, 0, 0));
  EXPECT_EQ(LoadCamera(eight).distortion, (std::array<double, 5>{0.1, 0.2, 0.3, 0.4, 0.5}));
}

TEST(CameraModelTest, LoadsRosCameraInfoYaml) {
  TempDir dir;
  const auto path = WriteFile(dir / "ros.yaml", R"(image_width: 640
image_height: 480
camera_name: auv_down
camera_matrix:
  rows: 3
  cols: 3
  data: [500.0, 0.0, 320.5, 0.0, 501.0, 240.5, 0.0, 0.0, 1.0]
distortion_model: plumb_bob
distortion_coefficients:
  rows: 1
  cols: 5
  data: [-0.1, 0.01, 0.0, 0.0, 0.0]
)");
  const CameraModel c = LoadCamera(path.string());
  EXPECT_EQ(c.width, 640);
  EXPECT_DOUBLE_EQ(c.fx, 500.0);
  EXPECT_DOUBLE_EQ(c.fy, 501.0);
  EXPECT_DOUBLE_EQ(c.cx, 320.5);
  EXPECT_DOUBLE_EQ(c.cy, 240.5);
  EXPECT_DOUBLE_EQ(c.distortion[0], -0.1);
}

TEST(CameraModelTest, BrokenOpenCvFileNamesTheFile) {
  TempDir dir;
  const std::string path = WriteFile(dir / "broken.yaml", "image_width: [640\n  : :\n").string();
  const InputError e = ExpectInputError([&] { LoadCamera(path); });
  EXPECT_EQ(e.file(), path);
  EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
}

TEST(CameraModelTest, OpenCvFileMissingFieldsNameTheField) {
  TempDir dir;
  const std::string path = (dir / "partial.yaml").string();
  {
    cv::FileStorage fs(path, cv::FileStorage::WRITE);
    fs << "image_width" << 640 << "image_height" << 480;
    fs << "camera_matrix" << cv::Mat(cv::Matx33d(500, 0, 320, 0, 500, 240, 0, 0, 1));
  }
  InputError e = ExpectInputError([&] { LoadCamera(path); });
  EXPECT_EQ(e.file(), path);
  EXPECT_EQ(e.field(), "distortion_coefficients");

  const std::string no_width = (dir / "nowidth.xml").string();
  {
    cv::FileStorage fs(no_width, cv::FileStorage::WRITE);
    fs << "image_height" << 480;
  }
  e = ExpectInputError([&] { LoadCamera(no_width); });
  EXPECT_EQ(e.field(), "image_width");

  const std::string bad_k = (dir / "badk.yaml").string();
  {
    cv::FileStorage fs(bad_k, cv::FileStorage::WRITE);
    fs << "image_width" << 640 << "image_height" << 480;
    fs << "camera_matrix" << cv::Mat(cv::Matx22d(500, 0, 0, 500));
  }
  e = ExpectInputError([&] { LoadCamera(bad_k); });
  EXPECT_EQ(e.field(), "camera_matrix");
  EXPECT_NE(std::string(e.what()).find("3x3"), std::string::npos);
}

TEST(CameraModelTest, JsonErrorsNameFileAndField) {
  TempDir dir;
  struct Case {
    const char* json;
    const char* field;
  };
  const Case cases[] = {
      {R"({"height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": 4})", "width"},
      {R"({"width": 0, "height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": 4})", "width"},
      {R"({"width": 10, "height": 8.5, "fx": 5, "fy": 5, "cx": 5, "cy": 4})", "height"},
      {R"({"width": 10, "height": 8})", "fx"},
      {R"({"width": 10, "height": 8, "fx": 5, "cx": 5, "cy": 4})", "fy"},
      {R"({"width": 10, "height": 8, "fx": -5, "fy": 5, "cx": 5, "cy": 4})", "fx"},
      {R"({"width": 10, "height": 8, "fx": 5, "fy": 5, "cx": 11, "cy": 4})", "cx"},
      {R"({"width": 10, "height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": "4"})", "cy"},
      {R"({"width": 10, "height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": 4, "distortion": [1, 2, 3, 4, 5, 6, 7]})",
       "distortion"},
      {R"({"width": 10, "height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": 4, "distortion": "none"})", "distortion"},
      {R"({"width": 10, "height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": 4, "mount": {"offset_m": [1, 2]}})",
       "mount.offset_m"},
      {R"({"width": 10, "height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": 4, "mount": {"pitch": 3}})", "mount.pitch"},
      {R"({"width": 10, "height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": 4, "distorsion": [0.1]})", "distorsion"},
  };
  for (const Case& c : cases) {
    const std::string path = WriteFile(dir / "bad.json", c.json).string();
    const InputError e = ExpectInputError([&] { LoadCamera(path); });
    EXPECT_EQ(e.file(), path) << c.json;
    EXPECT_EQ(e.field(), c.field) << c.json << " -> " << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    EXPECT_NE(std::string(e.what()).find(c.field), std::string::npos);
  }
}

TEST(CameraModelTest, JsonSyntaxErrorReportsLine) {
  TempDir dir;
  const std::string path = WriteFile(dir / "syntax.json", "{\n  \"width\": 10,\n  \"height\": ,\n}\n").string();
  const InputError e = ExpectInputError([&] { LoadCamera(path); });
  EXPECT_EQ(e.file(), path);
  EXPECT_EQ(e.line(), 3);
  EXPECT_NE(std::string(e.what()).find(path + ":3"), std::string::npos);
}

TEST(CameraModelTest, MissingFileAndUnknownExtension) {
  TempDir dir;
  const std::string missing = (dir / "nope.json").string();
  EXPECT_EQ(ExpectInputError([&] { LoadCamera(missing); }).file(), missing);
  const std::string txt = WriteFile(dir / "cam.txt", "fx 5").string();
  const InputError e = ExpectInputError([&] { LoadCamera(txt); });
  EXPECT_EQ(e.file(), txt);
  EXPECT_NE(std::string(e.what()).find(".json"), std::string::npos);
}

TEST(CameraModelTest, DefaultMountingLooksDownWithImageTopToBow) {
  CameraModel c = CameraFromFocalLength(8, 12.9, 696, 520);
  const Eigen::Matrix3d r = c.BodyFromCamera();
  EXPECT_TRUE(r.col(0).isApprox(Eigen::Vector3d(0, 1, 0)));   // image right -> starboard
  EXPECT_TRUE(r.col(1).isApprox(Eigen::Vector3d(-1, 0, 0)));  // image down -> aft
  EXPECT_TRUE(r.col(2).isApprox(Eigen::Vector3d(0, 0, 1)));   // optical axis -> down
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);

  // Mount pitch +10 (about body y) tilts the optical axis forward.
  c.mount_rpy_deg = {0, 10, 0};
  const Eigen::Vector3d axis = c.BodyFromCamera().col(2);
  EXPECT_NEAR(axis.x(), std::sin(10 * M_PI / 180), 1e-12);
  EXPECT_NEAR(axis.z(), std::cos(10 * M_PI / 180), 1e-12);
}

TEST(CameraModelTest, DistortUndistortRoundTrip) {
  CameraModel c = CameraFromFocalLength(8, 12.9, 696, 520);
  c.distortion = {-0.3, 0.1, 0.001, -0.002, 0.0};
  const std::vector<cv::Point2d> ideal = {{10, 20}, {347.5, 259.5}, {690, 500}, {-0.5, -0.5}};
  const auto raw = c.Distort(ideal);
  EXPECT_GT(cv::norm(raw[0] - ideal[0]), 1.0);  // the lens really moves it
  const auto back = c.Undistort(raw);
  for (size_t i = 0; i < ideal.size(); ++i) {
    EXPECT_NEAR(back[i].x, ideal[i].x, 1e-6);
    EXPECT_NEAR(back[i].y, ideal[i].y, 1e-6);
  }
}

TEST(CameraModelTest, HostileNumbersNameTheirField) {
  TempDir dir;
  struct Case {
    std::string json, field;
    int line;
  };
  const std::string base = R"({"width": 10, "height": 8, "fy": 5, "cx": 5, "cy": 4,)";
  const Case cases[] = {
      {base + "\n \"fx\": 1e999}", "fx", 2},  // a number JSON cannot hold
      {R"({"width": 10, "height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": 4,
           "mount": {"roll_deg": 0, "pitch_deg": -1e999}})",
       "mount.pitch_deg", 2},
      {base + R"("fx": 5, "distortion": [0.1, 1e400]})", "distortion", 1},
      {R"({"width": 99999999999, "height": 8, "fx": 5, "fy": 5, "cx": 5, "cy": 4})", "width", 0},
      {R"({"width": 10, "height": 200000, "fx": 5, "fy": 5, "cx": 5, "cy": 4})", "height", 0},
      {base + R"("fx": 1e-9})", "fx", 0},  // a field of view of nearly 180 degrees
      {base + R"("fx": 1e300})", "fx", 0},
      {base + R"("fx": 5, "distortion": [1e300, 1e300]})", "distortion", 0},
      {base + R"("fx": 5, "mount": {"offset_m": [1e300, 0, 0]}})", "mount.offset_m", 0},
  };
  for (const Case& c : cases) {
    const std::string path = WriteFile(dir / "bad.json", c.json).string();
    const InputError e = ExpectInputError([&] { LoadCamera(path); });
    EXPECT_EQ(e.file(), path) << c.json;
    EXPECT_EQ(e.field(), c.field) << c.json << " -> " << e.what();
    EXPECT_EQ(e.line(), c.line) << c.json << " -> " << e.what();
  }
  const std::string overflow = WriteFile(dir / "inf.json", base + "\n \"fx\": 1e999}").string();
  EXPECT_NE(std::string(ExpectInputError([&] { LoadCamera(overflow); }).what()).find("1e999 is out of range"),
            std::string::npos);
}

TEST(CameraModelTest, OversizedAndOddFilesAreRefusedByName) {
  TempDir dir;
  const std::string big = WriteFile(dir / "big.json", std::string(2 << 20, ' ') + "{}").string();
  const InputError e = ExpectInputError([&] { LoadCamera(big); });
  EXPECT_NE(std::string(e.what()).find("too large for a camera file"), std::string::npos) << e.what();
  for (const std::string yaml :
       {"%YAML:1.0\nimage_width: 10\nimage_height: 8\ncamera_matrix: {rows: 100000, cols: 100000, data: [1]}\n",
        "%YAML:1.0\nimage_width: 1e300\nimage_height: 8\n",
        "%YAML:1.0\ncamera_matrix: !!opencv-matrix\n  rows: -3\n"}) {
    const std::string path = WriteFile(dir / "odd.yaml", yaml).string();
    EXPECT_EQ(ExpectInputError([&] { LoadCamera(path); }).file(), path) << yaml;
  }
  // A FIFO would block the reader until something writes to it.
  const std::string fifo = (dir / "camera.json").string();
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(std::string(ExpectInputError([&] { LoadCamera(fifo); }).what()).find("not a regular file"),
            std::string::npos);
}

}  // namespace
}  // namespace seamap
