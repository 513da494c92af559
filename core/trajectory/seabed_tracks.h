#pragma once
// Seabed points from frames whose poses are KNOWN (the navigation, or a
// refined trajectory): features matched between overlapping frames, the
// matches chained into multi-view tracks, each track triangulated in the
// mission's local frame (east, north, up; height_grid.h's datum).
//
//  - Pairs: frames whose footprints on the expected seabed (the plane
//    altitude_m below each frame) overlap, found through a hash grid of the
//    footprint centres (cost linear in the survey), at most
//    `max_partners_per_frame` a frame, spread from the nearest to the widest
//    baseline (wide baselines fix heights, near ones chain the tracks).
//  - Matching guided by the poses: a feature of the new frame is looked for
//    only along its epipolar segment in the older frame, the part of its ray
//    within `max_relief_m` of the expected seabed; Lowe's ratio among those
//    candidates; one match per older feature (the closest descriptor).
//  - Tracks: union-find over the matched features; a track holding two
//    features of one frame is dropped (a false match somewhere).
//  - Triangulation: tracks of `min_views` frames or more (on rendered
//    surveys 17 % of two-view tracks are false against 2 % of four-view
//    ones); least squares on the rays, then Gauss-Newton on the
//    reprojection error; rejected when a view is off by more than
//    `max_reprojection_px` (dropping the worst view while more than
//    `min_views` remain), the
//    rays meet at less than `min_ray_angle_deg`, the point is behind a camera
//    or further than `max_relief_m` from the expected seabed (fish,
//    particles). Its height sigma is the Gauss-Newton covariance scaled by
//    the residuals (never below `pixel_sigma_px`).
//  - Memory: frames are taken in order; a frame's features are freed once
//    no later frame overlaps it, and a track is finished (triangulated, its
//    union-find nodes freed) once all its frames are.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/terrain/seabed_point.h"
#include "core/trajectory/frame_features.h"

namespace seamap {

struct TrackOptions {
  double max_relief_m = 1.5;         // --max-relief: how far the seabed may lie from the plane at the measured altitude
  double epipolar_px = 2.0;          // match gate: distance from the epipolar segment, ideal pixels
  double ratio = 0.8;                // Lowe's ratio test
  double min_overlap = 0.2;          // share of a footprint two frames must share to be matched
  int max_partners_per_frame = 8;    // older frames a new frame is matched with
  int min_views = 3;                 // frames a track must be seen in (two-view tracks hold most false matches)
  double max_reprojection_px = 1.5;  // largest residual of a kept view
  double min_ray_angle_deg = 2.0;    // widest angle between a track's rays must reach this
  double pixel_sigma_px = 0.3;       // floor of the feature position noise in the sigma
  void Check() const;                // InputError naming the option
};

// A camera as the triangulation sees it: in the mission's local frame with
// axes east, north, up.
struct TrackCamera {
  Eigen::Matrix3d world_from_camera = Eigen::Matrix3d::Identity();  // camera (OpenCV) vectors to (east, north, up)
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();               // (east, north, up), up = -depth_m
  double seabed_up_m = 0;  // the expected seabed below it: -(depth_m + altitude_m)
};
TrackCamera TrackCameraOf(const CameraModel& camera, const VehiclePose& pose);

// Ideal pixel of a world point; false when it is not in front of the camera.
bool ProjectToIdeal(const CameraModel& camera, const TrackCamera& view, const Eigen::Vector3d& point_m,
                    Eigen::Vector2d* ideal_px);

struct TrackObservation {
  int frame = 0;         // index into the frames given
  int feature = 0;       // index into that frame's features
  cv::Point2f ideal_px;  // where it was seen (undistorted full-resolution pixels)
};

// One triangulated track, for a bundle adjustment to reuse.
struct SeabedTrack {
  std::vector<TrackObservation> observations;  // one per frame, kept views only
  Eigen::Vector3d east_north_up_m = Eigen::Vector3d::Zero();
  double sigma_up_m = 0;
  double reprojection_rms_px = 0;
  double ray_angle_deg = 0;  // widest angle between two of its rays
};

struct SeabedTracks {
  std::vector<SeabedTrack> tracks;  // accepted ones
  SeabedPoints points;              // points[k] is tracks[k]'s point
};

struct TrackReport {
  int frames = 0, frames_without_features = 0;
  long pairs = 0, matches = 0;
  long tracks = 0;          // candidate tracks (two views or more)
  long rejected_views = 0;  // fewer than min_views
  long rejected_conflict = 0, rejected_reprojection = 0, rejected_ray_angle = 0, rejected_seabed = 0;
  long points = 0;
  int peak_frames_in_memory = 0;  // frames whose features were held at once
  size_t peak_feature_bytes = 0;
};

// Called once per frame, in order; an empty FrameFeatures for a frame
// without usable features.
using FeatureSource = std::function<FrameFeatures(int frame)>;
using TrackProgress = std::function<void(int frames_done, int frames_total)>;

SeabedTracks BuildSeabedTracks(const std::vector<VehiclePose>& poses, const CameraModel& camera,
                               const FeatureSource& features, const TrackOptions& options, TrackReport* report,
                               const TrackProgress& progress = nullptr);

// One track's triangulation (exposed for tests and a bundle adjustment's
// start): false with *why ("views", "reprojection", "ray angle", "seabed", "behind")
// when rejected. `track` gets the point, sigma and the kept observations.
bool TriangulateTrack(const CameraModel& camera, const std::vector<TrackCamera>& views, const TrackOptions& options,
                      SeabedTrack* track, std::string* why);

}  // namespace seamap
