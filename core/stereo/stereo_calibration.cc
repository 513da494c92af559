#include "core/stereo/stereo_calibration.h"

#include <cmath>
#include <filesystem>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

cv::Mat ReadMat(const cv::FileStorage& fs, const std::string& key, const std::string& path) {
  const cv::FileNode node = fs[key];
  if (node.empty() || node.isNone()) throw InputError(path, 0, key, "missing; expected a matrix");
  cv::Mat m;
  try {
    node >> m;
  } catch (const cv::Exception&) {
    m.release();
  }
  if (m.empty()) throw InputError(path, 0, key, "expected a matrix (!!opencv-matrix)");
  m.convertTo(m, CV_64F);
  for (auto it = m.begin<double>(); it != m.end<double>(); ++it)
    if (!std::isfinite(*it)) throw InputError(path, 0, key, "expected finite numbers");
  return m;
}

cv::Matx33d ReadCameraMatrix(const cv::FileStorage& fs, const std::string& key, const std::string& path) {
  const cv::Mat m = ReadMat(fs, key, path);
  if (m.rows != 3 || m.cols != 3) throw InputError(path, 0, key, "expected a 3x3 camera matrix");
  if (m.at<double>(1, 0) != 0 || m.at<double>(2, 0) != 0 || m.at<double>(2, 1) != 0 || m.at<double>(2, 2) != 1)
    throw InputError(path, 0, key, "expected [fx s cx; 0 fy cy; 0 0 1]");
  return cv::Matx33d(m);
}

std::vector<double> ReadDistortion(const cv::FileStorage& fs, const std::string& key, const std::string& path) {
  const cv::FileNode node = fs[key];
  if (node.empty() || node.isNone()) return {};  // no distortion
  const cv::Mat m = ReadMat(fs, key, path);
  if (m.rows != 1 && m.cols != 1) throw InputError(path, 0, key, "expected a 1xN or Nx1 vector");
  const size_t n = m.total();
  if (!(n == 4 || n == 5 || n == 8 || n == 12 || n == 14 || n == 0))
    throw InputError(path, 0, key, "expected 4, 5, 8, 12 or 14 coefficients, got " + std::to_string(n));
  return std::vector<double>(m.begin<double>(), m.end<double>());
}

int ReadPositiveInt(const cv::FileNode& n, const std::string& key, const std::string& path) {
  if (!n.isInt() && !n.isReal()) throw InputError(path, 0, key, "expected a positive integer");
  const double v = static_cast<double>(n);
  if (!(v > 0) || v != std::floor(v)) throw InputError(path, 0, key, "expected a positive integer");
  return static_cast<int>(v);
}

cv::Size ReadImageSize(const cv::FileStorage& fs, const std::string& path) {
  const cv::FileNode size = fs["image_size"];
  if (!size.empty() && !size.isNone()) {
    if (!size.isSeq() || size.size() != 2) throw InputError(path, 0, "image_size", "expected [width, height]");
    return {ReadPositiveInt(size[0], "image_size", path), ReadPositiveInt(size[1], "image_size", path)};
  }
  for (const char* key : {"image_width", "image_height"})
    if (fs[key].empty() || fs[key].isNone())
      throw InputError(path, 0, key, "missing; expected image_width and image_height (or image_size: [w, h])");
  return {ReadPositiveInt(fs["image_width"], "image_width", path),
          ReadPositiveInt(fs["image_height"], "image_height", path)};
}

std::vector<cv::Point2d> UndistortRectify(const std::vector<cv::Point2d>& raw, const cv::Matx33d& k,
                                          const std::vector<double>& d, const cv::Matx33d& r, const cv::Matx34d& p) {
  std::vector<cv::Point2d> out;
  if (raw.empty()) return out;
  cv::undistortPoints(raw, out, k, d, r, p,
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  return out;
}

}  // namespace

bool RectifiedRig::Project(const Eigen::Vector3d& left_xyz, cv::Point2d* left_px, cv::Point2d* right_px) const {
  const Eigen::Vector3d p = rect_from_left * left_xyz;
  if (p.z() <= 1e-9) return false;
  const double inv_z = 1 / p.z();
  *left_px = {f * p.x() * inv_z + cx, f * p.y() * inv_z + cy};
  *right_px = {f * (p.x() - baseline_m) * inv_z + cx, left_px->y};
  return true;
}

Eigen::Vector3d RectifiedRig::Triangulate(const cv::Point2d& left_px, const cv::Point2d& right_px) const {
  const double disparity = left_px.x - right_px.x;
  const double z = f * baseline_m / disparity;
  // Rows differ only by noise: their mean is the better estimate.
  const double y = 0.5 * (left_px.y + right_px.y);
  const Eigen::Vector3d rect((left_px.x - cx) * z / f, (y - cy) * z / f, z);
  // Back from the rectified frame: forgetting R1^T tilts the whole model.
  return rect_from_left.transpose() * rect;
}

Eigen::Matrix3d RectifiedRig::TriangulationCovariance(const cv::Point2d& left_px, const cv::Point2d& right_px,
                                                      double sigma_px) const {
  // Jacobian of (X, Y, Z) in the rectified frame w.r.t. (uL, uR, v), v the mean row.
  const double d = left_px.x - right_px.x;
  const double z = f * baseline_m / d;
  const double xl = left_px.x - cx, y = 0.5 * (left_px.y + right_px.y) - cy;
  Eigen::Matrix3d j;
  // X = xl B / d, Y = y B / d, Z = f B / d.
  j << baseline_m / d - xl * baseline_m / (d * d), xl * baseline_m / (d * d), 0,  //
      -y * baseline_m / (d * d), y * baseline_m / (d * d), baseline_m / d,        //
      -z / d, z / d, 0;
  Eigen::Matrix3d noise = Eigen::Vector3d(1, 1, 0.5).asDiagonal();  // the mean row has half the variance
  noise *= sigma_px * sigma_px;
  const Eigen::Matrix3d rect_cov = j * noise * j.transpose();
  return rect_from_left.transpose() * rect_cov * rect_from_left;
}

void StereoCalibration::Check(const std::string& source) const {
  const auto focal = [&](const cv::Matx33d& k, const char* key) {
    if (!(k(0, 0) > 0) || !(k(1, 1) > 0)) throw InputError(source, 0, key, "focal lengths must be positive");
    if (!(k(0, 2) > 0 && k(0, 2) < image_size.width && k(1, 2) > 0 && k(1, 2) < image_size.height))
      throw InputError(source, 0, key, "the principal point lies outside the image");
  };
  focal(K1, "K1");
  focal(K2, "K2");
  const double baseline = cv::norm(T);
  if (!(baseline >= 0.02 && baseline <= 2))
    throw InputError(source, 0, "T",
                     "baseline |T| = " + std::to_string(baseline) + " m is implausible (expected 0.02-2 m, metres)");
  const Eigen::Matrix3d r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R.val);
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-5 || r.determinant() < 0)
    throw InputError(source, 0, "R", "not a rotation matrix");
  const double angle = Eigen::AngleAxisd(r).angle() * 180 / M_PI;
  if (angle > 20)
    throw InputError(source, 0, "R", "the cameras differ by " + std::to_string(angle) + " deg (expected < 20 deg)");
}

void StereoCalibration::Rectify() {
  cv::Mat r1, r2, p1, p2, q;
  cv::stereoRectify(K1, D1, K2, D2, image_size, R, T, r1, r2, p1, p2, q, cv::CALIB_ZERO_DISPARITY, 0);
  R1 = cv::Matx33d(r1);
  R2 = cv::Matx33d(r2);
  P1 = cv::Matx34d(p1);
  P2 = cv::Matx34d(p2);
  rig.f = P1(0, 0);
  rig.cx = P1(0, 2);
  rig.cy = P1(1, 2);
  // P2(0, 3) = -f B for a right camera on the right (T ~ (-B, 0, 0)).
  rig.baseline_m = -P2(0, 3) / P2(0, 0);
  rig.rect_from_left = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R1.val);
}

std::vector<cv::Point2d> StereoCalibration::RectifyLeft(const std::vector<cv::Point2d>& raw_px) const {
  return UndistortRectify(raw_px, K1, D1, R1, P1);
}

std::vector<cv::Point2d> StereoCalibration::RectifyRight(const std::vector<cv::Point2d>& raw_px) const {
  return UndistortRectify(raw_px, K2, D2, R2, P2);
}

cv::Point2d StereoCalibration::ProjectRaw(const Eigen::Vector3d& left_xyz, bool right) const {
  cv::Vec3d p(left_xyz.x(), left_xyz.y(), left_xyz.z());
  if (right) p = R * p + T;
  std::vector<cv::Point3d> object{cv::Point3d(p[0], p[1], p[2])};
  std::vector<cv::Point2d> image;
  cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), right ? K2 : K1, right ? D2 : D1, image);
  return image[0];
}

Eigen::Matrix4d StereoCalibration::LeftFromRight() const {
  const Eigen::Matrix3d r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(R.val);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = r.transpose();
  m.topRightCorner<3, 1>() = -r.transpose() * Eigen::Vector3d(T[0], T[1], T[2]);
  return m;
}

StereoCalibration LoadStereoCalibration(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path, 0, "--calib", "no such file");
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    throw InputError(path, 0, "", "cannot parse the stereo calibration (OpenCV YAML/XML): " + e.msg);
  }
  if (!fs.isOpened()) throw InputError(path, 0, "", "cannot open the stereo calibration (OpenCV YAML/XML)");
  StereoCalibration c;
  c.image_size = ReadImageSize(fs, path);
  c.K1 = ReadCameraMatrix(fs, "K1", path);
  c.K2 = ReadCameraMatrix(fs, "K2", path);
  c.D1 = ReadDistortion(fs, "D1", path);
  c.D2 = ReadDistortion(fs, "D2", path);
  const cv::Mat r = ReadMat(fs, "R", path);
  if (r.total() == 3) {  // a rotation vector, as some tools write it
    cv::Mat m;
    cv::Rodrigues(r, m);
    c.R = cv::Matx33d(m);
  } else if (r.rows == 3 && r.cols == 3) {
    c.R = cv::Matx33d(r);
  } else {
    throw InputError(path, 0, "R", "expected a 3x3 rotation matrix");
  }
  const cv::Mat t = ReadMat(fs, "T", path);
  if (t.total() != 3) throw InputError(path, 0, "T", "expected a 3-vector (metres)");
  c.T = cv::Vec3d(t.at<double>(0), t.at<double>(1), t.at<double>(2));
  c.Check(path);
  c.Rectify();
  return c;
}

void SaveStereoCalibration(const StereoCalibration& c, const std::string& path) {
  cv::FileStorage fs(path, cv::FileStorage::WRITE);
  if (!fs.isOpened()) throw InputError(path, 0, "", "cannot write the stereo calibration");
  fs << "image_width" << c.image_size.width << "image_height" << c.image_size.height;
  fs << "K1" << cv::Mat(c.K1) << "D1" << cv::Mat(c.D1.empty() ? std::vector<double>(5, 0.0) : c.D1).reshape(1, 1);
  fs << "K2" << cv::Mat(c.K2) << "D2" << cv::Mat(c.D2.empty() ? std::vector<double>(5, 0.0) : c.D2).reshape(1, 1);
  fs << "R" << cv::Mat(c.R) << "T" << cv::Mat(c.T);
}

}  // namespace seamap
