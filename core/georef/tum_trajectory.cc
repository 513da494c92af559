#include "core/georef/tum_trajectory.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/util/error.h"
#include "core/util/input_file.h"

namespace seamap {
namespace {

const char* kFields[8] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};

}  // namespace

std::vector<Keyframe> ReadTumTrajectory(const std::string& path) {
  RegularFileBytes(path, "keyframe file");  // /dev/zero or a FIFO would never end
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "", "cannot open the keyframe file");
  std::vector<Keyframe> keyframes;
  std::string text;
  int number = 0;
  while (std::getline(in, text)) {
    ++number;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    const size_t start = text.find_first_not_of(" \t");
    if (start == std::string::npos || text[start] == '#') continue;
    std::istringstream fields(text);
    std::string field;
    double v[8];
    int n = 0;
    while (fields >> field) {
      if (n == 8) {
        ++n;
        break;
      }
      char* end = nullptr;
      v[n] = std::strtod(field.c_str(), &end);
      if (*end != '\0' || !std::isfinite(v[n]))
        throw InputError(path, number, kFields[n], "is not a number: '" + field + "'");
      ++n;
    }
    if (n != 8)
      throw InputError(path, number, "",
                       std::string("expected 8 numbers 'timestamp tx ty tz qx qy qz qw', got ") +
                           (n > 8 ? "more" : std::to_string(n)));
    if (!keyframes.empty() && !(v[0] > keyframes.back().time_s)) {
      std::ostringstream why;
      why.precision(15);
      why << "timestamp " << v[0] << " is not after the previous keyframe's " << keyframes.back().time_s << " (line "
          << keyframes.back().line << ")";
      throw InputError(path, number, "timestamp", why.str());
    }
    Keyframe k;
    k.time_s = v[0];
    k.position_slam = {v[1], v[2], v[3]};
    k.world_from_cam = Eigen::Quaterniond(v[7], v[4], v[5], v[6]);  // Eigen takes the scalar first
    const double norm = k.world_from_cam.norm();
    if (std::fabs(norm - 1.0) > 0.01) {
      std::ostringstream why;
      why << "quaternion (qx qy qz qw) has norm " << norm << ", expected 1 +- 0.01";
      throw InputError(path, number, "qw", why.str());
    }
    k.world_from_cam.normalize();
    k.line = number;
    keyframes.push_back(k);
  }
  if (keyframes.empty())
    throw InputError(path, 0, "", "no keyframes (expected lines 'timestamp tx ty tz qx qy qz qw')");
  return keyframes;
}

void WriteTumTrajectory(const std::string& path, const std::vector<Keyframe>& keyframes, const std::string& comment) {
  std::FILE* out = std::fopen(path.c_str(), "w");
  if (!out) throw InputError(path, 0, "", "cannot write the keyframe file");
  std::fprintf(out, "# timestamp tx ty tz qx qy qz qw%s%s\n", comment.empty() ? "" : "  ", comment.c_str());
  for (const Keyframe& k : keyframes) {
    const Eigen::Quaterniond& q = k.world_from_cam;
    std::fprintf(out, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", k.time_s, k.position_slam.x(), k.position_slam.y(),
                 k.position_slam.z(), q.x(), q.y(), q.z(), q.w());
  }
  if (std::fclose(out) != 0) throw InputError(path, 0, "", "cannot write the keyframe file");
}

}  // namespace seamap
