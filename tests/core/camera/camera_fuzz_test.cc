// Randomised camera files (tests/testing/fuzz.h): JSON and OpenCV YAML with
// hostile numbers and mangled bytes either load into a model that passes
// Validate, or stop with an InputError naming the file. Never a crash or
// another kind of exception.
#include <cmath>
#include <fstream>

#include <gtest/gtest.h>

#include "core/camera/camera_model.h"
#include "core/util/error.h"
#include "tests/testing/fuzz.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

using testing::Fuzz;
using testing::TempDir;

// The text with each number replaced, one time in `odds`, by a hostile value.
std::string WithHostileNumbers(Fuzz& fuzz, const std::string& text, size_t odds) {
  std::string out;
  for (size_t i = 0; i < text.size();) {
    const bool starts_number = (std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '-') &&
                               (i == 0 || !std::isalnum(static_cast<unsigned char>(text[i - 1])));
    if (!starts_number) {
      out += text[i++];
      continue;
    }
    size_t end = i + 1;
    while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '.' ||
                                 text[end] == 'e' || text[end] == '-'))
      ++end;
    out += fuzz.OneIn(odds) ? fuzz.HostileNumber() : text.substr(i, end - i);
    i = end;
  }
  return out;
}

void Check(Fuzz& fuzz, const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
  SCOPED_TRACE("case " + std::to_string(fuzz.cases()) + ":\n" + text.substr(0, 600));
  try {
    const CameraModel c = LoadCamera(path);
    EXPECT_NO_THROW(c.Validate(path));
    EXPECT_TRUE(std::isfinite(c.fx) && std::isfinite(c.fy) && std::isfinite(c.cx) && std::isfinite(c.cy));
    EXPECT_GT(c.width, 0);
    EXPECT_GT(c.height, 0);
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), path) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
  }
}

TEST(CameraFuzz, HostileJsonCameraFilesLoadValidOrAreRefusedByName) {
  TempDir dir;
  Fuzz fuzz;
  const std::string path = (dir / "camera.json").string();
  const std::string valid = R"({"width": 696, "height": 520, "fx": 620.2, "fy": 620.2, "cx": 347.5, "cy": 259.5,
 "distortion": [-0.05, 0.01, 0, 0, 0],
 "mount": {"roll_deg": 0.5, "pitch_deg": -1, "yaw_deg": 90, "offset_m": [0.1, 0, -0.2]}})";
  while (fuzz.More()) {
    std::string text = WithHostileNumbers(fuzz, valid, 4);
    if (fuzz.OneIn(3)) text = fuzz.Mutate(text);
    Check(fuzz, path, text);
  }
}

TEST(CameraFuzz, HostileOpenCvYamlCameraFilesLoadValidOrAreRefusedByName) {
  TempDir dir;
  Fuzz fuzz;
  const std::string path = (dir / "camera.yaml").string();
  const std::string valid = R"(%YAML:1.0
---
image_width: 696
image_height: 520
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 620.1550387596899, 0., 347.5, 0., 620.1550387596899, 259.5, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ -0.05, 0.01, 0., 0., 0. ]
)";
  while (fuzz.More()) {
    std::string text = WithHostileNumbers(fuzz, valid, 4);
    // Byte edits only after the "%YAML" line: OpenCV's parser is not ours.
    if (fuzz.OneIn(4)) text = text.substr(0, 15) + fuzz.Mutate(text.substr(15));
    Check(fuzz, path, text);
  }
}

}  // namespace
}  // namespace seamap
