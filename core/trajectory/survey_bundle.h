#pragma once
// The whole survey's refinement in 3-D (refine on relief): one robust bundle
// adjustment over every frame's pose and the seabed points tracked across
// frames, with the navigation as priors. Unknowns per frame: east, north and
// height (up = -depth) of the navigation reference point, heading, pitch and
// roll; per point: east, north, up. Residuals:
//  - reprojection: the point in the camera (core/camera/frame_projector.h's
//    NedFromCamera, mount offset included) against the observed ideal pixel,
//    in normalised coordinates over the pixel sigma, under CauchyLoss;
//  - navigation: relative east/north of consecutive frames over
//    sqrt(2 sigma_n^2 + (rho dt)^2) and heading change over sqrt(2) sigma_psi,
//    as the planar pose graph has them (pose_graph.h); absolute heading and
//    absolute east/north under HuberLoss, the latter as the navigation less
//    its drift over sigma_n, the drift a few unknowns of time (knots
//    drift_knot_s apart, steps within rho x the spacing, starting at zero;
//    nav_priors.h), or (drift_knot_s 0) as the pose graph has it, over
//    sqrt(sigma_n^2 + (rho tau)^2);
//  - AHRS pitch and roll (absolute), depth (absolute), all under HuberLoss;
//  - altitude, as a 4-beam DVL measures it (core/terrain/dvl_altitude.h):
//    the vehicle's height above the mean seabed height at its four beams'
//    footprints (with dvl_beam_angle_deg 0, one vertical beam: the seabed at
//    the nadir). Each beam's seabed is a plane of its own (height and two
//    slopes, one small block per beam and frame) that the tracked points
//    nearest the footprint lie on up to the seabed's curvature, one residual
//    per point: no residual holds two points, so all of them are eliminated.
// Points are eliminated by the Schur complement (SPARSE_SCHUR, or
// ITERATIVE_SCHUR in windows or without a sparse library); poses, beam planes and drift
// knots form the reduced system, 6 + 12 unknowns a frame. After a first solve,
// observations reprojecting further than reject_px are dropped and the
// problem solved again.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/camera/vehicle_pose.h"
#include "core/terrain/seabed_point.h"

namespace seamap {

struct SurveyBundleOptions {
  double nav_sigma_m = 0.05;            // stated position noise sigma_n (floor 1 mm)
  double nav_drift_m_per_s = 1.0 / 60;  // stated drift rate rho
  double heading_sigma_rad = 0.0175;    // stated heading noise (floor 0.01 deg)
  double attitude_sigma_rad = 0.0087;   // AHRS pitch and roll noise (0.5 deg)
  double depth_sigma_m = 0.05;          // depth sensor
  double altitude_sigma_m = 0.05;       // DVL / altimeter
  double dvl_beam_angle_deg =
      30;  // the altimeter: a 4-beam DVL (Janus beams this far off vertical); 0: one vertical beam
  // Tracked points that place the seabed under a beam: the plane through them
  // (4 or more spanning an area), else a level plane at their mean height.
  int altitude_points = 6;
  // A point lies on its beam's plane up to this share of the neighbourhood's
  // radius (0.15 x altitude): the seabed's curvature there (1 sigma).
  double beam_plane_sigma_share = 0.1;
  double pixel_sigma = 0.7;            // feature position noise, ideal pixels
  double reprojection_loss_scale = 2;  // CauchyLoss on whitened reprojection residuals
  double prior_loss_scale = 3;         // HuberLoss on absolute priors
  double reject_px = 4;                // observations reprojecting further are dropped before the second solve
  // The navigation's drift as unknowns: east and north at knots this far apart
  // in time, linear between them, each step within nav_drift x the spacing
  // (at least nav_sigma), the first within nav_sigma of zero; the absolute
  // position prior is then the navigation less its drift, within nav_sigma.
  // 0: the pose graph's absolute prior instead, sigma growing with the time
  // since the first frame (its drifted early frames then hold the map).
  double drift_knot_s = 10;
  // A frame held from an earlier window (SurveyBundleFrame::fixed) stays free
  // within this much of where that window left it: east, north and up in
  // metres, heading, pitch and roll in degrees. A lane held exactly passed its
  // error whole to the lane glued to it, and along a long survey the lanes
  // bent more with each one; held within 3 mm and 0.015 deg they still turned
  // further lane by lane past ~3,000 frames (docs/BUNDLE_WINDOWS.md, "Held
  // lanes that give"). 0: held exactly.
  double held_sigma_m = 0.01;
  double held_sigma_deg = 0.05;
  // The reduced system solved by conjugate gradients preconditioned by its
  // diagonal blocks (ITERATIVE_SCHUR, SCHUR_JACOBI) instead of factored
  // (SPARSE_SCHUR), whose cost grows ~W^2.3 with a window's W frames; set
  // for windows of a longer survey (docs/BUNDLE_WINDOWS.md, "A window's cost").
  bool iterative_schur = false;
  int max_iterations = 50, threads = 2;
  // The time the absolute position priors' drift grows from; none: the first
  // frame's (a window of a longer survey gives the survey's start).
  std::optional<double> prior_origin_time_s;
  void Check() const;  // InputError naming the option
};

struct SurveyBundleFrame {
  VehiclePose nav;    // as navigated: the priors
  VehiclePose start;  // where the solve starts (e.g. the planar refinement)
  double time_s = 0;
  bool fixed = false;  // held near `start` (solved in an earlier window, windowed_bundle.h; held_sigma_m)
};

struct SurveyBundleObservation {
  int frame = 0, point = 0;
  cv::Point2f ideal_px;  // undistorted pixel of the camera model
};

struct SurveyBundleResult {
  std::vector<VehiclePose> poses;   // refined: east, north, depth (= -up), heading, pitch, roll; altitude as navigated
  std::vector<SeabedPoint> points;  // refined; views = observations kept (0: dropped)
  std::vector<bool> observation_rejected;  // per observation
  std::vector<bool> nav_only;              // frames without a kept observation
  // Per frame, the altimeter's range as the solved map has it (the vehicle's
  // height above its beams' seabed planes, as BeamAltitudeResidual models it),
  // to compare with the measured altitude; NaN for a frame without a reading.
  std::vector<double> altitude_range_m;
  double rms_px_before = 0, rms_px_after = 0;  // kept observations, at the start and at the end
  double cost_before = 0, cost_after = 0;
  int iterations = 0;
  bool converged = false;
  std::string linear_solver;
  int points_solved = 0;      // points with two kept views or more, in the last solve
  int points_eliminated = 0;  // of those, eliminated by the Schur complement (all, by design)
};

// The navigation's drift knots when the bundle is one window of a longer
// survey (windowed_bundle.h): the knots are the survey's, those before the
// window were solved by earlier windows and are held, so the drift goes on
// across the seam instead of starting again at zero.
struct SurveyBundleDrift {
  double origin_time_s = 0;                  // knot 0's time (the survey's first frame)
  double knot_s = 10;                        // the knots' spacing
  std::vector<std::array<double, 2>> knots;  // drift (east, north) m per knot: start values in, solved out
  int held_knots = 0;                        // knots [0, held_knots) are held where they are
};

// points_start: one starting position per point (east, north, up); every
// observation's frame and point index in range. Throws InputError for bad
// options or indices. window_drift (a window of a longer survey): the drift
// knots to use in place of options.drift_knot_s's; solved on return.
SurveyBundleResult SolveSurveyBundle(const std::vector<SurveyBundleFrame>& frames, const CameraModel& camera,
                                     const std::vector<Eigen::Vector3d>& points_start,
                                     const std::vector<SurveyBundleObservation>& observations,
                                     const SurveyBundleOptions& options, SurveyBundleDrift* window_drift = nullptr);

// Where the ray of an ideal pixel of a frame at `pose` meets the level seabed
// `pose.altitude_m` below the vehicle: a starting point (east, north, up with
// up = -depth - altitude). Empty when the ray does not point down.
std::optional<Eigen::Vector3d> FlatSeabedPoint(const CameraModel& camera, const VehiclePose& pose,
                                               const cv::Point2f& ideal_px);

}  // namespace seamap
