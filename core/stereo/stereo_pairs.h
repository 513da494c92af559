#pragma once
// Stereo pairs in a folder: NAME_left.png + NAME_right.png, or left/NAME.png
// + right/NAME.png, sorted by NAME. A missing partner, an unreadable image or
// a size that differs from the calibration's is an InputError naming the file.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace seamap {

struct PairFiles {
  std::string name, left, right;
};

std::vector<PairFiles> ListStereoPairs(const std::string& dir);

struct LoadedPair {
  std::string name;
  cv::Mat left, right;  // 8-bit gray
};

LoadedPair LoadStereoPair(const PairFiles& files, cv::Size expected_size, const std::string& calibration_path);

}  // namespace seamap
