#include "core/trajectory/visual_odometry.h"

#include <algorithm>
#include <cmath>

#include <opencv2/features2d.hpp>

#include "core/camera/frame_projector.h"
#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

// The camera's height above a flat seabed: the altitude, measured at the
// navigation reference point, less the camera's mounting offset downwards.
double CameraHeight(const CameraModel& camera, const VehiclePose& nav) {
  return nav.altitude_m - (NedFromBody(nav) * camera.mount_offset_m).z();
}

}  // namespace

void VoOptions::Check() const {
  if (!(ratio > 0 && ratio <= 1)) throw InputError("", 0, "ratio", "expected a number in (0, 1]");
  if (!(min_parallax >= 0)) throw InputError("", 0, "min_parallax", "expected a number >= 0");
  if (!(max_interval_s > 0)) throw InputError("", 0, "max_interval_s", "expected a number > 0");
  if (!(altimeter_beam_deg >= 0 && altimeter_beam_deg < 60))
    throw InputError("", 0, "altimeter_beam_deg", "expected degrees in [0, 60)");
  features.Check();
}

VisualOdometry::VisualOdometry(const CameraModel& camera, const VoOptions& options, const Eigen::Vector3d& vo_sigma_mps)
    : camera_(camera), options_(options), vo_sigma_mps_(vo_sigma_mps), models_(options.two_view) {
  options_.Check();
}

bool VisualOdometry::TakeAsReference(const FrameFeatures& features, double time_s, const VehiclePose& nav) {
  if (static_cast<int>(features.ideal_px.size()) < options_.min_keypoints) {
    ++counts_.low_texture;
    return false;
  }
  Reference r;
  r.features = features;
  features.descriptors.convertTo(r.descriptors, CV_32F);
  r.time_s = time_s;
  r.nav = nav;
  reference_ = std::move(r);
  return true;
}

std::optional<VoMeasurement> VisualOdometry::Add(const FrameFeatures& features, double time_s, const VehiclePose& nav) {
  ++counts_.frames;
  if (!reference_) {
    TakeAsReference(features, time_s, nav);
    return std::nullopt;
  }
  Reference& ref = *reference_;
  const double interval = time_s - ref.time_s;
  if (!(interval > 0)) return std::nullopt;  // the same moment again
  if (static_cast<int>(features.ideal_px.size()) < options_.min_keypoints) {
    ++counts_.low_texture;
    if (interval > options_.max_interval_s) reference_.reset();  // too long without a frame to measure
    return std::nullopt;
  }
  if (SameFeatures(features, ref.features)) {  // a frozen camera repeating its photo: no motion measured
    ++counts_.identical;
    if (interval > options_.max_interval_s) {  // the same photo, taken now: the next one is measured from here
      ref.time_s = time_s;
      ref.nav = nav;
    }
    return std::nullopt;
  }

  // Matches by Lowe's ratio.
  cv::Mat current;
  features.descriptors.convertTo(current, CV_32F);
  std::vector<std::vector<cv::DMatch>> knn;
  cv::BFMatcher(cv::NORM_L2).knnMatch(current, ref.descriptors, knn, 2);
  std::vector<cv::Point2d> p1, p2;
  for (const auto& m : knn)
    if (m.size() == 2 && m[0].distance < options_.ratio * m[1].distance) {
      p1.push_back(ref.features.ideal_px[m[0].trainIdx]);
      p2.push_back(features.ideal_px[m[0].queryIdx]);
    }

  // The views' rotation from the attitude sensor, and the parallax it leaves.
  const Eigen::Matrix3d body_from_camera = camera_.BodyFromCamera();
  const Eigen::Matrix3d ned_from_ref = NedFromBody(ref.nav), ned_from_cur = NedFromBody(nav);
  const Eigen::Matrix3d cam2_from_cam1 =
      body_from_camera.transpose() * ned_from_cur.transpose() * ned_from_ref * body_from_camera;
  const cv::Matx33d k = camera_.K();
  const cv::Matx33d k_inv = k.inv();
  std::vector<double> parallax;
  for (size_t i = 0; i < p1.size(); ++i) {
    const cv::Vec3d ray = k_inv * cv::Vec3d(p1[i].x, p1[i].y, 1);
    const Eigen::Vector3d turned = cam2_from_cam1 * Eigen::Vector3d(ray[0], ray[1], ray[2]);
    const cv::Vec3d pixel = k * cv::Vec3d(turned.x(), turned.y(), turned.z());
    parallax.push_back(std::hypot(pixel[0] / pixel[2] - p2[i].x, pixel[1] / pixel[2] - p2[i].y));
  }
  const double median_parallax = Median(parallax);
  if (static_cast<int>(p1.size()) < options_.two_view.min_inliers) {
    ++counts_.low_texture;
    if (interval > options_.max_interval_s) TakeAsReference(features, time_s, nav);
    return std::nullopt;
  }
  if (median_parallax < options_.hover_parallax_px) {
    if (interval < options_.hover_s) return std::nullopt;
    // Hovering: the vehicle stayed put, to a pixel's worth of seabed.
    VoMeasurement m;
    m.time_s = time_s;
    m.interval_s = interval;
    m.body_velocity_mps.setZero();
    const double sigma = options_.hover_parallax_px * CameraHeight(camera_, nav) / camera_.fx / interval;
    m.covariance = Eigen::Matrix3d::Identity() * sigma * sigma;
    m.inliers = static_cast<int>(p1.size());
    ++counts_.hover;
    ++counts_.measurements;
    TakeAsReference(features, time_s, nav);
    return m;
  }
  if (median_parallax < options_.min_parallax * camera_.width && interval < options_.max_interval_s)
    return std::nullopt;  // not worth measuring yet: keep the reference

  const double height = CameraHeight(camera_, ref.nav);
  if (!(height > 0) || !std::isfinite(height)) {
    ++counts_.missing_altitude;
    TakeAsReference(features, time_s, nav);
    return std::nullopt;
  }
  PairGeometry geometry;
  geometry.K = k;
  geometry.image_size = {camera_.width, camera_.height};
  geometry.cam2_from_cam1_ahrs = cam2_from_cam1;
  // NED down, in camera-1 axes: where the seabed is.
  geometry.seabed_normal_cam1 = body_from_camera.transpose() * ned_from_ref.transpose() * Eigen::Vector3d::UnitZ();
  geometry.height_m = height;
  // The camera sits at mount_offset_m from the navigation's reference point
  // (where the altitude is measured), body axes.
  geometry.altimeter_cam1_m = -(body_from_camera.transpose() * camera_.mount_offset_m);
  if (options_.altimeter_beam_deg > 0) {
    const double tilt = options_.altimeter_beam_deg * M_PI / 180;
    for (int k = 0; k < 4; ++k) {
      const double azimuth = (45 + 90 * k) * M_PI / 180;
      const Eigen::Vector3d beam_body(std::sin(tilt) * std::cos(azimuth), std::sin(tilt) * std::sin(azimuth),
                                      std::cos(tilt));
      geometry.altimeter_beams_cam1.push_back(body_from_camera.transpose() * beam_body);
    }
  }
  const TwoViewMotion motion = models_.Next(p1, p2, geometry);
  TakeAsReference(features, time_s, nav);
  if (motion.model == MotionModel::kNone) {
    ++counts_.failed_pairs;
    return std::nullopt;
  }
  // The camera moved by c (camera-1 axes); the vehicle's reference point by
  // that less the lever arm's turn. Mean body velocity at the current frame.
  const Eigen::Vector3d moved_ned = ned_from_ref * body_from_camera * motion.displacement_cam1_m -
                                    (ned_from_cur - ned_from_ref) * camera_.mount_offset_m;
  VoMeasurement m;
  m.time_s = time_s;
  m.interval_s = interval;
  m.body_velocity_mps = ned_from_cur.transpose() * moved_ned / interval;
  m.covariance = vo_sigma_mps_.cwiseProduct(vo_sigma_mps_).asDiagonal();
  m.model = motion.model;
  m.inliers = motion.inliers;
  ++counts_.measurements;
  (motion.model == MotionModel::kHomography ? counts_.homography : counts_.essential)++;
  counts_.motion_inliers += m.inliers;
  return m;
}

}  // namespace seamap
