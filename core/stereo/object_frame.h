#pragma once
// `stereo-model --object-frame points.csv`: moves the model from the first
// overview pair's left camera frame into the object's own drawing frame,
// from named points with known drawing coordinates (metres) and their
// pixels in the first overview pair.
// CSV header: name,x,y,z,u_left,v_left[,u_right,v_right] (raw pixels).
// With right pixels the points are triangulated and fitted (a similarity
// first: a scale outside 0.99-1.01 means wrong units), else cv::solvePnP
// (SQPNP, >= 4 points). At least 3 non-collinear points; an RMS over 2 cm is
// an error naming the worst point.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/stereo/object_model.h"

namespace seamap {

struct ObjectFramePoint {
  std::string name;
  int line = 0;
  Eigen::Vector3d drawing;
  cv::Point2d left_px, right_px;
  bool has_right = false;
};

std::vector<ObjectFramePoint> ReadObjectFramePoints(const std::string& path);

struct ObjectFrameFit {
  Rigid drawing_from_model = Rigid::Identity();
  double rms_m = 0;
  std::vector<double> residual_m;  // per point
};

ObjectFrameFit FitObjectFrame(const std::vector<ObjectFramePoint>& points, const StereoCalibration& calibration,
                              const std::string& path, double max_rms_m = 0.02);

// Points, covariances and view poses into the drawing frame; frame = "drawing".
void MoveModel(ObjectModel* model, const Rigid& drawing_from_model);

}  // namespace seamap
