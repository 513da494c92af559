#include "core/stereo/rigid_transform.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <Eigen/Dense>

#include "core/util/error.h"

namespace seamap {

nlohmann::json RigidToJson(const Rigid& a_from_b) {
  nlohmann::json rows = nlohmann::json::array();
  const Eigen::Matrix4d m = a_from_b.matrix();
  for (int r = 0; r < 4; ++r) rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  return rows;
}

namespace {

std::string ShortNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", v);
  return text;
}

}  // namespace

Rigid RigidFromJson(const nlohmann::json& value, const std::string& source, const std::string& field) {
  const auto fail = [&](const std::string& why) { throw InputError(source, 0, field, why); };
  if (!value.is_array() || value.size() != 4) fail("expected a 4x4 matrix (4 rows of 4 numbers)");
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    if (!value[r].is_array() || value[r].size() != 4) fail("expected a 4x4 matrix (4 rows of 4 numbers)");
    for (int c = 0; c < 4; ++c) {
      if (!value[r][c].is_number()) fail("expected numbers in the 4x4 matrix");
      m(r, c) = value[r][c].get<double>();
    }
  }
  if (m.row(3).cwiseAbs().head<3>().maxCoeff() > 1e-9 || std::abs(m(3, 3) - 1) > 1e-9)
    fail("the last row must be 0 0 0 1");
  const Eigen::Matrix3d rot = m.topLeftCorner<3, 3>();
  if ((rot.transpose() * rot - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 || rot.determinant() < 0)
    fail("the rotation part is not a rotation (orthonormal, determinant +1)");
  // Metres in any fixed frame (UTM included); 1e300 would reach the joint
  // solution as inf and still be "found".
  constexpr double kMaxTranslationM = 1e7;
  for (int r = 0; r < 3; ++r)
    if (!(std::abs(m(r, 3)) <= kMaxTranslationM))
      fail("translation " + std::string("xyz").substr(r, 1) + " = " + ShortNumber(m(r, 3)) +
           " m is out of range, expected at most 1e7 m from the frame's origin");
  Rigid t = Rigid::Identity();
  t.linear() = rot;
  t.translation() = m.topRightCorner<3, 1>();
  return t;
}

Eigen::Matrix<double, 6, 1> RigidToVector(const Rigid& a_from_b) {
  const Eigen::AngleAxisd aa(a_from_b.linear());
  Eigen::Matrix<double, 6, 1> v;
  v.head<3>() = aa.axis() * aa.angle();
  v.tail<3>() = a_from_b.translation();
  return v;
}

Rigid RigidFromVector(const Eigen::Matrix<double, 6, 1>& rotvec_t) {
  const Eigen::Vector3d w = rotvec_t.head<3>();
  const double angle = w.norm();
  Rigid t = Rigid::Identity();
  t.linear() = angle < 1e-15 ? Eigen::Matrix3d::Identity() : Eigen::AngleAxisd(angle, w / angle).toRotationMatrix();
  t.translation() = rotvec_t.tail<3>();
  return t;
}

Rigid FitRigid(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst) {
  const int n = static_cast<int>(src.size());
  Eigen::Matrix3Xd a(3, n), b(3, n);
  for (int k = 0; k < n; ++k) a.col(k) = src[k], b.col(k) = dst[k];
  // Third argument false: rigid, no scale (its default would fit a similarity).
  return Rigid(Eigen::umeyama(a, b, false));
}

double CheckPointError(const Rigid& est_object_from_camera, const Rigid& true_object_from_camera,
                       const std::vector<Eigen::Vector3d>& check_points_object) {
  if (check_points_object.empty()) return 0;
  const Rigid est_camera_from_object = est_object_from_camera.inverse();
  const Rigid true_camera_from_object = true_object_from_camera.inverse();
  double sum = 0;
  for (const Eigen::Vector3d& p : check_points_object)
    sum += (est_camera_from_object * p - true_camera_from_object * p).norm();
  return sum / static_cast<double>(check_points_object.size());
}

double PointSigmaM(const Rigid& object_from_camera, const Eigen::Matrix<double, 6, 6>& covariance,
                   const std::vector<Eigen::Vector3d>& points_object) {
  if (points_object.empty()) return 0;
  const Eigen::Matrix<double, 6, 1> v = RigidToVector(object_from_camera);
  // Jacobian of camera_from_object * P by central differences: the rotation
  // vector's chart has no simple closed form away from identity.
  constexpr double kStep = 1e-6;
  std::array<Rigid, 6> plus, minus;
  for (int i = 0; i < 6; ++i) {
    Eigen::Matrix<double, 6, 1> d = Eigen::Matrix<double, 6, 1>::Zero();
    d[i] = kStep;
    plus[i] = RigidFromVector(v + d).inverse();
    minus[i] = RigidFromVector(v - d).inverse();
  }
  double sum = 0;
  for (const Eigen::Vector3d& p : points_object) {
    Eigen::Matrix<double, 3, 6> jacobian;
    for (int i = 0; i < 6; ++i) jacobian.col(i) = (plus[i] * p - minus[i] * p) / (2 * kStep);
    sum += (jacobian * covariance * jacobian.transpose()).trace();
  }
  return std::sqrt(std::max(0.0, sum / static_cast<double>(points_object.size())));
}

double RotationAngleDeg(const Eigen::Matrix3d& rotation) {
  return Eigen::AngleAxisd(rotation).angle() * 180 / M_PI;
}

}  // namespace seamap
