#include "core/stereo/stereo_pairs.h"

#include <algorithm>
#include <filesystem>
#include <map>

#include "core/enhance/pixel_format.h"
#include "core/image/image_read.h"
#include "core/stereo/sift_features.h"
#include "core/util/error.h"

namespace seamap {
namespace fs = std::filesystem;
namespace {

bool IsImage(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".tiff" || ext == ".bmp";
}

}  // namespace

std::vector<PairFiles> ListStereoPairs(const std::string& dir) {
  if (!fs::is_directory(dir)) throw InputError(dir, 0, "--pairs", "no such folder");
  std::map<std::string, PairFiles> pairs;
  const auto add = [&](const std::string& name, const fs::path& file, bool right) {
    PairFiles& p = pairs[name];
    p.name = name;
    std::string& slot = right ? p.right : p.left;
    if (!slot.empty()) throw InputError(file.string(), 0, "--pairs", "two images for the same side of pair " + name);
    slot = file.string();
  };
  if (fs::is_directory(fs::path(dir) / "left") || fs::is_directory(fs::path(dir) / "right")) {
    for (const char* side : {"left", "right"}) {
      const fs::path sub = fs::path(dir) / side;
      if (!fs::is_directory(sub))
        throw InputError(sub.string(), 0, "--pairs", "missing: left/ and right/ folders come together");
      for (const auto& e : fs::directory_iterator(sub))
        if (e.is_regular_file() && IsImage(e.path())) add(e.path().stem().string(), e.path(), side[0] == 'r');
    }
  } else {
    for (const auto& e : fs::directory_iterator(dir)) {
      if (!e.is_regular_file() || !IsImage(e.path())) continue;
      const std::string stem = e.path().stem().string();
      for (const auto& [suffix, right] :
           {std::pair{std::string("_left"), false}, std::pair{std::string("_right"), true}})
        if (stem.size() > suffix.size() && stem.compare(stem.size() - suffix.size(), suffix.size(), suffix) == 0)
          add(stem.substr(0, stem.size() - suffix.size()), e.path(), right);
    }
  }
  std::vector<PairFiles> out;
  for (auto& [name, p] : pairs) {
    if (p.left.empty()) throw InputError(p.right, 0, "--pairs", "pair " + name + " has no left image");
    if (p.right.empty()) throw InputError(p.left, 0, "--pairs", "pair " + name + " has no right image");
    out.push_back(p);
  }
  if (out.empty())
    throw InputError(dir, 0, "--pairs", "no stereo pairs (expected NAME_left.png + NAME_right.png, or left/ + right/)");
  return out;
}

LoadedPair LoadStereoPair(const PairFiles& files, cv::Size expected_size, const std::string& calibration_path) {
  LoadedPair pair;
  pair.name = files.name;
  for (const auto& [path, image] : {std::pair{&files.left, &pair.left}, std::pair{&files.right, &pair.right}}) {
    std::string problem;
    // The size the header claims is checked before decoding: a 24000x18000
    // PNG of a few KB would take 1.3 GB to find it is not the rig's size.
    const auto header = ReadImageHeader(*path, &problem);
    if (!header) throw InputError(*path, 0, "", "cannot read the image: " + problem);
    if (header->width > 0 && (header->width != expected_size.width || header->height != expected_size.height))
      throw InputError(*path, 0, "",
                       cv::format("image is %lldx%lld but %s is for %dx%d images; not decoded",
                                  static_cast<long long>(header->width), static_cast<long long>(header->height),
                                  calibration_path.c_str(), expected_size.width, expected_size.height));
    const cv::Mat m = ReadGuardedImage(*path, &problem);
    if (m.empty()) throw InputError(*path, 0, "", "cannot read the image: " + problem);
    if (m.size() != expected_size)
      throw InputError(*path, 0, "",
                       cv::format("image is %dx%d but %s is for %dx%d images", m.cols, m.rows, calibration_path.c_str(),
                                  expected_size.width, expected_size.height));
    *image = ToGray8(m);
  }
  return pair;
}

}  // namespace seamap
