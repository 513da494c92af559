#pragma once
// Rigid transforms between coordinate systems, named `a_from_b` (p_a = R p_b + t),
// and how they are written: a 4x4 row-major matrix in JSON, a 6-vector
// (rotation vector [rad], translation [m]) for the optimiser.
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

namespace seamap {

using Rigid = Eigen::Isometry3d;

// [[r00, r01, r02, t0], ..., [0, 0, 0, 1]]
nlohmann::json RigidToJson(const Rigid& a_from_b);
// Throws InputError(source, 0, field, ...) unless a 4x4 matrix whose rotation
// is orthonormal (within 1e-6) with determinant +1 and last row 0 0 0 1,
// and whose translation is within 1e7 m of the origin on each axis.
Rigid RigidFromJson(const nlohmann::json& value, const std::string& source, const std::string& field);

// (rotation vector, translation) <-> transform.
Eigen::Matrix<double, 6, 1> RigidToVector(const Rigid& a_from_b);
Rigid RigidFromVector(const Eigen::Matrix<double, 6, 1>& rotvec_t);

// Least-squares rigid fit without scale (Umeyama): dst_from_src. At least
// 3 non-collinear pairs.
Rigid FitRigid(const std::vector<Eigen::Vector3d>& src, const std::vector<Eigen::Vector3d>& dst);

// The seed paper's error: each check point P (object coordinates) is mapped
// into the camera with the estimated and with the true object_from_camera;
// the mean distance between the two, metres.
double CheckPointError(const Rigid& est_object_from_camera, const Rigid& true_object_from_camera,
                       const std::vector<Eigen::Vector3d>& check_points_object);

// The check-point error a pose's uncertainty predicts: the RMS distance the
// points (object coordinates) move in the camera frame under the covariance
// of object_from_camera's RigidToVector parameters (rotation vector first),
// to first order. Unlike the camera's position sigma in the object frame, it
// is not inflated by the lever arm from the object to the camera.
double PointSigmaM(const Rigid& object_from_camera, const Eigen::Matrix<double, 6, 6>& covariance,
                   const std::vector<Eigen::Vector3d>& points_object);

// Angle of a rotation, degrees.
double RotationAngleDeg(const Eigen::Matrix3d& rotation);

}  // namespace seamap
