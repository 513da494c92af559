#include "core/camera/camera_model.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>
#include <opencv2/calib3d.hpp>

#include "core/geo/rotation.h"
#include "core/util/error.h"

namespace seamap {
namespace {

using nlohmann::json;

constexpr double kDegToRad = M_PI / 180.0;
constexpr double kMaxFocalPx = 1e7;

// Brown-Conrady coefficient counts OpenCV knows; we model the first five and
// accept longer vectors only when the extra (rational/thin-prism/tilt) terms are 0.
bool IsSupportedDistortionCount(size_t n) {
  return n <= 5 || n == 8 || n == 12 || n == 14;
}

std::string Lowercase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// Fills camera.distortion from any supported coefficient count.
void SetDistortion(CameraModel& camera, const std::vector<double>& coeffs, const std::string& path,
                   const std::string& field) {
  if (!IsSupportedDistortionCount(coeffs.size()))
    throw InputError(
        path, 0, field,
        "expected 0-5, 8, 12 or 14 coefficients (k1, k2, p1, p2, k3, ...), got " + std::to_string(coeffs.size()));
  for (size_t i = 0; i < coeffs.size(); ++i) {
    if (!std::isfinite(coeffs[i]))
      throw InputError(path, 0, field, "expected finite numbers, element " + std::to_string(i) + " is not");
    if (i >= 5 && coeffs[i] != 0)
      throw InputError(path, 0, field,
                       "expected only k1, k2, p1, p2, k3 to be non-zero: the rational, thin-prism "
                       "and tilt terms (element " +
                           std::to_string(i) + ") are not supported");
  }
  camera.distortion = {};
  for (size_t i = 0; i < std::min<size_t>(5, coeffs.size()); ++i) camera.distortion[i] = coeffs[i];
}

// ---------- JSON ----------

struct JsonReader {
  const std::string& path;

  const json* Find(const json& obj, const std::string& key) const {
    auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }
  double Number(const json& obj, const std::string& key, const std::string& field) const {
    const json* v = Find(obj, key);
    if (!v) throw InputError(path, 0, field, "missing; expected a number");
    if (!v->is_number()) throw InputError(path, 0, field, "expected a number, got " + v->dump());
    return v->get<double>();
  }
  double NumberOr(const json& obj, const std::string& key, const std::string& field, double fallback) const {
    return Find(obj, key) ? Number(obj, key, field) : fallback;
  }
  int Integer(const json& obj, const std::string& key) const {
    const json* v = Find(obj, key);
    if (!v) throw InputError(path, 0, key, "missing; expected a positive integer");
    if (!v->is_number_integer()) throw InputError(path, 0, key, "expected a positive integer, got " + v->dump());
    const int64_t value = v->is_number_unsigned() && v->get<uint64_t>() > INT64_MAX ? INT64_MAX : v->get<int64_t>();
    if (value <= 0 || value > kMaxImageSide)
      throw InputError(path, 0, key,
                       "expected a positive integer up to " + std::to_string(kMaxImageSide) + ", got " + v->dump());
    return static_cast<int>(value);
  }
  std::vector<double> Numbers(const json& v, const std::string& field) const {
    if (!v.is_array()) throw InputError(path, 0, field, "expected an array of numbers");
    std::vector<double> out;
    for (const auto& x : v) {
      if (!x.is_number()) throw InputError(path, 0, field, "expected numbers, got " + x.dump());
      out.push_back(x.get<double>());
    }
    return out;
  }
  void RejectUnknownKeys(const json& obj, const std::set<std::string>& known, const std::string& prefix) const {
    for (const auto& item : obj.items()) {
      if (known.count(item.key())) continue;
      std::string list;
      for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
      throw InputError(path, 0, prefix + item.key(), "unknown field; expected one of " + list);
    }
  }
};

int LineOfByte(const std::string& text, size_t byte) {
  byte = std::min(byte, text.size());
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + byte, '\n'));
}

// A camera file is a few hundred bytes; a larger one is not one.
constexpr std::uintmax_t kMaxCameraFileBytes = 1 << 20;

std::string ReadCameraText(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > kMaxCameraFileBytes)
    throw InputError(path, 0, "",
                     "is " + std::to_string(size) + " bytes, too large for a camera file (limit " +
                         std::to_string(kMaxCameraFileBytes) + ")");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open camera file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// Parses while keeping the key being read ("mount.pitch_deg"), so that a
// number JSON cannot hold (1e999) is reported with its field and line.
json ParseJson(const std::string& text, const std::string& path) {
  std::vector<std::string> keys;
  auto track = [&keys](int depth, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::key && depth >= 1) {
      keys.resize(static_cast<size_t>(depth));
      keys.back() = parsed.is_string() ? parsed.get<std::string>() : "";
    } else if (event == json::parse_event_t::object_end) {
      keys.resize(std::min(keys.size(), static_cast<size_t>(std::max(depth, 0))));
    }
    return true;
  };
  try {
    return json::parse(text, track);
  } catch (const json::parse_error& e) {
    // e.byte is 1-based position of the offending character.
    throw InputError(path, LineOfByte(text, e.byte > 0 ? e.byte - 1 : 0), "", std::string("invalid JSON: ") + e.what());
  } catch (const json::exception& e) {
    std::string field;
    for (const auto& k : keys) field += (field.empty() ? "" : ".") + k;
    // "number overflow parsing '1e999'": find the number for its line.
    const std::string what = e.what();
    const size_t quote = what.find('\'');
    const std::string number =
        quote == std::string::npos ? "" : what.substr(quote + 1, what.find('\'', quote + 1) - quote - 1);
    const size_t at = number.empty() ? std::string::npos : text.find(number);
    throw InputError(path, at == std::string::npos ? 0 : LineOfByte(text, at), field,
                     number.empty() ? std::string("invalid JSON: ") + e.what()
                                    : "number " + number + " is out of range; expected a finite number");
  }
}

CameraModel LoadJson(const std::string& path) {
  const std::string text = ReadCameraText(path);
  const json j = ParseJson(text, path);
  if (!j.is_object()) throw InputError(path, 1, "", "expected a JSON object");

  JsonReader r{path};
  r.RejectUnknownKeys(j,
                      {"width", "height", "fx", "fy", "cx", "cy", "focal_mm", "pixel_pitch_um", "distortion", "mount",
                       "name", "comment"},
                      "");
  CameraModel c;
  c.width = r.Integer(j, "width");
  c.height = r.Integer(j, "height");
  if (c.width <= 0) throw InputError(path, 0, "width", "expected a positive integer");
  if (c.height <= 0) throw InputError(path, 0, "height", "expected a positive integer");

  if (!r.Find(j, "fx") && r.Find(j, "focal_mm")) {
    const double focal = r.Number(j, "focal_mm", "focal_mm");
    const double pitch = r.Number(j, "pixel_pitch_um", "pixel_pitch_um");
    if (!(focal > 0) || !std::isfinite(focal))
      throw InputError(path, 0, "focal_mm", "expected a positive focal length in millimetres");
    if (!(pitch > 0) || !std::isfinite(pitch))
      throw InputError(path, 0, "pixel_pitch_um", "expected a positive pixel pitch in micrometres");
    const CameraModel shortcut = CameraFromFocalLength(focal, pitch, c.width, c.height);
    c.fx = shortcut.fx;
    c.fy = shortcut.fy;
    c.cx = r.NumberOr(j, "cx", "cx", shortcut.cx);
    c.cy = r.NumberOr(j, "cy", "cy", shortcut.cy);
  } else {
    if (!r.Find(j, "fx"))
      throw InputError(path, 0, "fx",
                       "missing; expected fx, fy, cx, cy in pixels (or focal_mm and "
                       "pixel_pitch_um)");
    c.fx = r.Number(j, "fx", "fx");
    c.fy = r.Number(j, "fy", "fy");
    c.cx = r.Number(j, "cx", "cx");
    c.cy = r.Number(j, "cy", "cy");
  }

  if (const json* d = r.Find(j, "distortion")) SetDistortion(c, r.Numbers(*d, "distortion"), path, "distortion");

  if (const json* m = r.Find(j, "mount")) {
    if (!m->is_object()) throw InputError(path, 0, "mount", "expected an object");
    r.RejectUnknownKeys(*m, {"roll_deg", "pitch_deg", "yaw_deg", "offset_m"}, "mount.");
    c.mount_rpy_deg = {r.NumberOr(*m, "roll_deg", "mount.roll_deg", 0),
                       r.NumberOr(*m, "pitch_deg", "mount.pitch_deg", 0),
                       r.NumberOr(*m, "yaw_deg", "mount.yaw_deg", 0)};
    if (const json* o = r.Find(*m, "offset_m")) {
      const auto xyz = r.Numbers(*o, "mount.offset_m");
      if (xyz.size() != 3)
        throw InputError(path, 0, "mount.offset_m", "expected [forward, starboard, down] in metres (3 numbers)");
      c.mount_offset_m = {xyz[0], xyz[1], xyz[2]};
    }
  }
  c.Validate(path);
  return c;
}

// ---------- OpenCV FileStorage (YAML / XML) ----------

// Reads a matrix written by cv::FileStorage (!!opencv-matrix) or the ROS
// camera_info layout ({rows, cols, data: [...]}) into a flat vector.
std::vector<double> ReadMatrix(const cv::FileNode& node, const std::string& path, const std::string& field, int* rows,
                               int* cols) {
  if (node.empty() || node.isNone()) throw InputError(path, 0, field, "missing; expected a matrix");
  cv::Mat m;
  try {
    node >> m;
  } catch (const cv::Exception&) {
    m.release();
  }
  if (m.empty() && node.isMap() && node["data"].isSeq()) {
    std::vector<double> data;
    node["data"] >> data;
    const int r = node["rows"].empty() ? 1 : static_cast<int>(node["rows"]);
    const int c = node["cols"].empty() ? static_cast<int>(data.size()) : static_cast<int>(node["cols"]);
    if (r <= 0 || c <= 0 || int64_t{r} * c != static_cast<int64_t>(data.size()))
      throw InputError(path, 0, field, "expected rows*cols data values");
    *rows = r;
    *cols = c;
    return data;
  }
  if (m.empty()) throw InputError(path, 0, field, "expected a matrix (!!opencv-matrix or {rows, cols, data})");
  m.convertTo(m, CV_64F);
  *rows = m.rows;
  *cols = m.cols;
  return std::vector<double>(m.begin<double>(), m.end<double>());
}

int ReadImageSize(const cv::FileStorage& fs, const std::string& key, const std::string& path) {
  const cv::FileNode n = fs[key];
  if (n.empty() || n.isNone()) throw InputError(path, 0, key, "missing; expected a positive integer");
  if (!n.isInt() && !n.isReal()) throw InputError(path, 0, key, "expected a positive integer");
  const double v = static_cast<double>(n);
  if (!(v > 0) || v != std::floor(v) || v > kMaxImageSide)
    throw InputError(path, 0, key, "expected a positive integer up to " + std::to_string(kMaxImageSide));
  return static_cast<int>(v);
}

CameraModel ReadFileStorage(const std::string& path) {
  cv::FileStorage fs;
  try {
    std::string content = ReadCameraText(path);
    const std::string ext = Lowercase(std::filesystem::path(path).extension().string());
    // ROS camera_info files are plain YAML without OpenCV's "%YAML:1.0" line,
    // which OpenCV needs to recognise the format.
    int format = cv::FileStorage::FORMAT_XML;
    if (ext != ".xml") {
      format = cv::FileStorage::FORMAT_YAML;
      if (content.rfind("%YAML", 0) != 0) content = "%YAML:1.0\n" + content;
    }
    fs.open(content, cv::FileStorage::READ | cv::FileStorage::MEMORY | format);
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "", "cannot parse OpenCV calibration file: " + e.msg);
  }
  if (!fs.isOpened()) throw InputError(path, 0, "", "cannot open OpenCV calibration file");

  CameraModel c;
  c.width = ReadImageSize(fs, "image_width", path);
  c.height = ReadImageSize(fs, "image_height", path);

  int rows = 0, cols = 0;
  const auto k = ReadMatrix(fs["camera_matrix"], path, "camera_matrix", &rows, &cols);
  if (rows != 3 || cols != 3) throw InputError(path, 0, "camera_matrix", "expected a 3x3 matrix");
  if (k[1] != 0 || k[3] != 0 || k[6] != 0 || k[7] != 0 || k[8] != 1)
    throw InputError(path, 0, "camera_matrix", "expected [fx 0 cx; 0 fy cy; 0 0 1] (no skew)");
  c.fx = k[0];
  c.cx = k[2];
  c.fy = k[4];
  c.cy = k[5];

  const auto d = ReadMatrix(fs["distortion_coefficients"], path, "distortion_coefficients", &rows, &cols);
  if (rows != 1 && cols != 1) throw InputError(path, 0, "distortion_coefficients", "expected a 1xN or Nx1 vector");
  SetDistortion(c, d, path, "distortion_coefficients");
  c.Validate(path);
  return c;
}

// OpenCV's reader throws its own exceptions on odd content (a matrix of the
// wrong kind, a huge "rows"), and standard ones from deep inside (a string
// of a size read from the file): they become InputErrors naming the file.
CameraModel LoadFileStorage(const std::string& path) {
  try {
    return ReadFileStorage(path);
  } catch (const InputError&) {
    throw;
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "", "cannot read OpenCV calibration file: " + e.msg);
  } catch (const std::exception& e) {
    throw InputError(path, 0, "", std::string("cannot read OpenCV calibration file: ") + e.what());
  }
}

}  // namespace

cv::Mat CameraModel::DistortionCoeffs() const {
  cv::Mat d(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) d.at<double>(0, i) = distortion[i];
  return d;
}

bool CameraModel::HasDistortion() const {
  return std::any_of(distortion.begin(), distortion.end(), [](double v) { return v != 0; });
}

Eigen::Matrix3d CameraModel::BodyFromCamera() const {
  return seamap::BodyFromCamera(CameraLooking::kDown, mount_rpy_deg);
}

std::vector<cv::Point2d> CameraModel::Undistort(const std::vector<cv::Point2d>& raw) const {
  if (!HasDistortion() || raw.empty()) return raw;
  std::vector<cv::Point2d> out;
  // More iterations than OpenCV's default 5 so strong lenses invert to ~1e-9 px.
  cv::undistortPoints(raw, out, K(), DistortionCoeffs(), cv::noArray(), K(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-12));
  return out;
}

std::vector<cv::Point2d> CameraModel::Distort(const std::vector<cv::Point2d>& ideal) const {
  if (!HasDistortion() || ideal.empty()) return ideal;
  std::vector<cv::Point3d> rays;
  rays.reserve(ideal.size());
  for (const auto& p : ideal) rays.emplace_back((p.x - cx) / fx, (p.y - cy) / fy, 1.0);
  std::vector<cv::Point2d> out;
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K(), DistortionCoeffs(), out);
  return out;
}

void CameraModel::Validate(const std::string& source) const {
  if (width <= 0) throw InputError(source, 0, "width", "expected a positive image width in pixels");
  if (height <= 0) throw InputError(source, 0, "height", "expected a positive image height in pixels");
  if (width > kMaxImageSide) throw InputError(source, 0, "width", "expected at most " + std::to_string(kMaxImageSide));
  if (height > kMaxImageSide)
    throw InputError(source, 0, "height", "expected at most " + std::to_string(kMaxImageSide));
  if (!(fx > 0) || !std::isfinite(fx) || fx > kMaxFocalPx)
    throw InputError(source, 0, "fx", "expected a positive finite focal length in pixels (at most 1e7)");
  if (!(fy > 0) || !std::isfinite(fy) || fy > kMaxFocalPx)
    throw InputError(source, 0, "fy", "expected a positive finite focal length in pixels (at most 1e7)");
  if (!(cx >= 0 && cx <= width)) throw InputError(source, 0, "cx", "expected a principal point in [0, width]");
  if (!(cy >= 0 && cy <= height)) throw InputError(source, 0, "cy", "expected a principal point in [0, height]");
  // Wider than 170 degrees the seabed footprint runs towards the horizon.
  const double tan_half_fov = std::tan(85 * kDegToRad);
  if (std::max(cx, width - cx) / fx > tan_half_fov)
    throw InputError(source, 0, "fx", "gives a field of view over 170 degrees: too short a focal length for the width");
  if (std::max(cy, height - cy) / fy > tan_half_fov)
    throw InputError(source, 0, "fy",
                     "gives a field of view over 170 degrees: too short a focal length for the height");
  for (double d : distortion)
    if (!std::isfinite(d)) throw InputError(source, 0, "distortion", "expected finite coefficients");
  if (!mount_rpy_deg.allFinite()) throw InputError(source, 0, "mount", "expected finite roll/pitch/yaw in degrees");
  if (!mount_offset_m.allFinite() || mount_offset_m.norm() > 100)
    throw InputError(source, 0, "mount.offset_m", "expected finite offsets in metres, within 100 m");
  if (HasDistortion()) {
    // Coefficients so large that the lens moves the image corners by more
    // than ten image diagonals (1e300) describe no lens, and overflow later.
    const double l = -0.5, t = -0.5, r = width - 0.5, b = height - 0.5;
    const std::vector<cv::Point2d> corners{{l, t}, {r, t}, {r, b}, {l, b}};
    const std::vector<cv::Point2d> moved = Distort(corners);
    const double limit = 10 * std::hypot(width, height);
    for (size_t i = 0; i < corners.size(); ++i)
      if (!(cv::norm(moved[i] - corners[i]) <= limit))
        throw InputError(source, 0, "distortion",
                         "the coefficients move the image corners by more than ten image diagonals");
  }
}

CameraModel LoadCamera(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw InputError(path, 0, "", "camera file not found");
  // Reading a FIFO would wait for a writer for ever.
  if (!std::filesystem::is_regular_file(status))
    throw InputError(path, 0, "", "is not a regular file; expected a camera calibration file");
  const std::string ext = Lowercase(std::filesystem::path(path).extension().string());
  if (ext == ".json") return LoadJson(path);
  if (ext == ".yaml" || ext == ".yml" || ext == ".xml") return LoadFileStorage(path);
  throw InputError(path, 0, "", "unknown camera file type '" + ext + "'; expected .json, .yaml, .yml or .xml");
}

void SaveCameraJson(const CameraModel& camera, const std::string& path) {
  json j = {{"width", camera.width},
            {"height", camera.height},
            {"fx", camera.fx},
            {"fy", camera.fy},
            {"cx", camera.cx},
            {"cy", camera.cy},
            {"distortion", camera.distortion},
            {"mount",
             {{"roll_deg", camera.mount_rpy_deg.x()},
              {"pitch_deg", camera.mount_rpy_deg.y()},
              {"yaw_deg", camera.mount_rpy_deg.z()},
              {"offset_m", {camera.mount_offset_m.x(), camera.mount_offset_m.y(), camera.mount_offset_m.z()}}}}};
  std::ofstream out(path);
  out << j.dump(2) << "\n";
  if (!out) throw InputError(path, 0, "", "cannot write camera file");
}

CameraModel CameraFromFocalLength(double focal_mm, double pixel_pitch_um, int width, int height) {
  if (!(focal_mm > 0) || !std::isfinite(focal_mm))
    throw InputError("", 0, "focal_mm", "expected a positive focal length in millimetres");
  if (!(pixel_pitch_um > 0) || !std::isfinite(pixel_pitch_um))
    throw InputError("", 0, "pixel_pitch_um", "expected a positive pixel pitch in micrometres");
  CameraModel c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = focal_mm * 1000.0 / pixel_pitch_um;
  // Pixel centres sit at integer coordinates, so the image centre is at (w-1)/2.
  c.cx = width / 2.0 - 0.5;
  c.cy = height / 2.0 - 0.5;
  return c;
}

}  // namespace seamap
