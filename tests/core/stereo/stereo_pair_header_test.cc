// Issue 33, row 9: a stereo pair's photos are checked against the rig's
// image size by their headers, before decoding: a PNG of a few bytes whose
// header says 24000 x 18000 took 1.3 GB to be found the wrong size.
#include <fstream>

#include <gtest/gtest.h>

#include "core/stereo/stereo_pairs.h"
#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap {
namespace {

// A PNG signature and IHDR chunk only (8-bit gray): all a header check reads.
std::string PngHeader(uint32_t width, uint32_t height) {
  std::string png("\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR", 16);
  for (uint32_t v : {width, height})
    for (int shift = 24; shift >= 0; shift -= 8) png.push_back(static_cast<char>((v >> shift) & 0xFF));
  png += std::string("\x08\0\0\0\0\0\0\0\0", 9);  // depth 8, gray, deflate, no filter, no interlace; CRC
  return png;
}

TEST(StereoPairHeader, AHugeHeaderIsRefusedBySizeUndecoded) {
  testing::TempDir dir;
  PairFiles files{"p", (dir / "p_left.png").string(), (dir / "p_right.png").string()};
  std::ofstream(files.left, std::ios::binary) << PngHeader(24000, 18000);
  std::ofstream(files.right, std::ios::binary) << PngHeader(640, 480);
  try {
    LoadStereoPair(files, cv::Size(640, 480), "stereo.yaml");
    ADD_FAILURE() << "loaded";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), files.left);
    EXPECT_NE(std::string(e.what()).find("image is 24000x18000 but stereo.yaml is for 640x480 images; not decoded"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace seamap
