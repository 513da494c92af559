#pragma once
// Seed 003's motion per image pair, done carefully: both a homography (the
// seabed is a plane) and an essential matrix are fitted by RANSAC to the
// matched ideal pixels; the model in use is kept while it passes (the paper's
// persistent switching rule) and chosen by inlier counts at the start and
// after a pair where both failed. A model passes when at least 80 % of its
// inliers lie in front of both cameras (cheirality), there are enough of them
// spread over a fifth of the image, and its rotation agrees with the AHRS
// (which also rejects the wrong twin of the planar essential-matrix
// ambiguity). Scale comes from the altitude, the range the altimeter (a DVL)
// measures to the seabed below the vehicle: the inliers are triangulated at
// the model's unit baseline and scaled so that the seabed they describe
// right below the altimeter lies at the measured height (a local plane
// through the points near that footprint). On relief the seabed below the
// vehicle is not the mean plane of the view: a plane fitted to the whole
// view puts a bump under the vehicle at the wrong range (docs/TERRAIN.md).
//
// OpenCV maps camera-1 points into camera 2: X2 = R X1 + t. The camera moved
// by c = -R^T t, in camera-1 axes.
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace seamap {

enum class MotionModel { kNone, kHomography, kEssential };
const char* MotionModelName(MotionModel m);

struct TwoViewOptions {
  double homography_px = 1.5;  // RANSAC thresholds in ideal pixels
  double essential_px = 1.0;
  double min_cheirality = 0.8;  // the paper's
  int min_inliers = 30;
  // A model that explains under half of the matches is not this scene's (a
  // homography fitted to one depth of a rough seabed passes the paper's tests).
  double min_inlier_share = 0.5;
  double min_area = 0.2;              // inliers' hull over the image area
  double max_rotation_error_deg = 3;  // against the AHRS
  double homography_share = 0.45;     // start with H when n_H / (n_H + n_E) is above this
  // The scale's neighbourhood: triangulated points within this share of the
  // seabed's distance from the altimeter's footprint (grown when too few).
  double nadir_radius = 0.2;
  // false: the pre-relief scale, from the plane through the whole view (the
  // homography's own plane distance; a plane fitted to E's points).
  bool scale_at_nadir = true;
};

// What is known of a pair besides its matches.
struct PairGeometry {
  cv::Matx33d K;  // ideal pinhole pixels
  cv::Size image_size;
  Eigen::Matrix3d cam2_from_cam1_ahrs;  // rotation between the views from the attitude sensor
  Eigen::Vector3d seabed_normal_cam1;   // unit, camera-1 axes, pointing from the camera to the seabed
  double height_m = 0;                  // camera 1 above the seabed, along the normal
  // Where the altimeter is, seen from camera 1 (camera-1 axes, metres), and
  // where it looks: a DVL's altitude is the mean vertical range of its
  // beams (unit directions, camera-1 axes); none: straight down along the
  // normal. height_m is then the camera's height over the seabed the beams
  // see: the altitude less the camera's offset below the altimeter.
  Eigen::Vector3d altimeter_cam1_m = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> altimeter_beams_cam1;
};

struct TwoViewMotion {
  MotionModel model = MotionModel::kNone;
  Eigen::Matrix3d cam2_from_cam1 = Eigen::Matrix3d::Identity();
  Eigen::Vector3d displacement_cam1_m = Eigen::Vector3d::Zero();  // c, metres, camera-1 axes
  int inliers = 0;
  double cheirality = 0;  // share of inliers in front of both cameras
  double rotation_error_deg = 0;
  std::string failure;  // why the model failed, when it did
};

// One model's motion, or a failure naming why.
TwoViewMotion EstimateWithModel(MotionModel model, const std::vector<cv::Point2d>& ideal1,
                                const std::vector<cv::Point2d>& ideal2, const PairGeometry& geometry,
                                const TwoViewOptions& options);

// The switching rule over a sequence of pairs.
class ModelSwitch {
 public:
  explicit ModelSwitch(TwoViewOptions options = {}) : options_(options) {}
  // The motion of the next pair; model kNone when both models fail (the next
  // pair then chooses again by inlier counts).
  TwoViewMotion Next(const std::vector<cv::Point2d>& ideal1, const std::vector<cv::Point2d>& ideal2,
                     const PairGeometry& geometry);
  MotionModel in_use() const { return in_use_; }

 private:
  TwoViewOptions options_;
  MotionModel in_use_ = MotionModel::kNone;  // kNone: choose by counts
};

// The plane n.X = d best fitting points (least squares, trimmed of points
// beyond three robust sigmas or `tolerance`), n unit and d > 0; nullopt with
// under 20 supporting points.
struct Plane {
  Eigen::Vector3d normal;
  double distance;
};
std::optional<Plane> FitPlane(const std::vector<Eigen::Vector3d>& points, double tolerance);

// The distance along `normal` (unit, towards the seabed) from the origin to
// the seabed the points describe at lateral position `footprint` (its part
// along the normal is ignored): a plane fitted robustly to the points within
// `radius_share` of their median distance from that footprint, the
// neighbourhood grown while it holds under 20 points; nullopt when it never
// does. Points and footprint in the same (any) unit.
std::optional<double> SeabedDistanceAt(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& normal,
                                       const Eigen::Vector3d& footprint, double radius_share);

}  // namespace seamap
