#include "core/stereo/object_frame.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <opencv2/calib3d.hpp>

#include "core/util/error.h"
#include "core/util/input_file.h"

namespace seamap {

std::vector<ObjectFramePoint> ReadObjectFramePoints(const std::string& path) {
  RegularFileBytes(path, "points file", "--object-frame");  // not /dev/zero, not a FIFO
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "--object-frame", "cannot open the points file");
  std::string line;
  std::getline(in, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  const bool with_right = line == "name,x,y,z,u_left,v_left,u_right,v_right";
  if (!with_right && line != "name,x,y,z,u_left,v_left")
    throw InputError(path, 1, "header", "expected name,x,y,z,u_left,v_left[,u_right,v_right]");
  const char* fields[] = {"x", "y", "z", "u_left", "v_left", "u_right", "v_right"};
  std::vector<ObjectFramePoint> out;
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::stringstream row(line);
    std::string cell;
    ObjectFramePoint p;
    p.line = number;
    std::getline(row, p.name, ',');
    double v[7];
    const int n = with_right ? 7 : 5;
    for (int k = 0; k < n; ++k) {
      if (!std::getline(row, cell, ',')) throw InputError(path, number, fields[k], "missing");
      char* end = nullptr;
      v[k] = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0' || !std::isfinite(v[k]))
        throw InputError(path, number, fields[k], "expected a number, got '" + cell + "'");
    }
    p.drawing = Eigen::Vector3d(v[0], v[1], v[2]);
    p.left_px = {v[3], v[4]};
    p.has_right = with_right;
    if (with_right) p.right_px = {v[5], v[6]};
    out.push_back(p);
  }
  return out;
}

ObjectFrameFit FitObjectFrame(const std::vector<ObjectFramePoint>& points, const StereoCalibration& calibration,
                              const std::string& path, double max_rms_m) {
  if (points.size() < 3) throw InputError(path, 0, "--object-frame", "at least 3 points are needed");
  Eigen::Matrix3Xd drawing(3, points.size());
  for (size_t k = 0; k < points.size(); ++k) drawing.col(k) = points[k].drawing;
  const Eigen::Matrix3Xd centred = drawing.colwise() - drawing.rowwise().mean();
  const Eigen::Vector3d sv = Eigen::JacobiSVD<Eigen::MatrixXd>(centred).singularValues();
  if (sv[1] < 1e-3 * std::max(1e-9, sv[0]) || sv[1] < 1e-4)
    throw InputError(path, 0, "--object-frame", "the points are collinear: the frame is not determined");

  ObjectFrameFit fit;
  if (points[0].has_right) {
    std::vector<cv::Point2d> raw_l, raw_r;
    for (const auto& p : points) raw_l.push_back(p.left_px), raw_r.push_back(p.right_px);
    const auto rect_l = calibration.RectifyLeft(raw_l), rect_r = calibration.RectifyRight(raw_r);
    Eigen::Matrix3Xd model(3, points.size());
    for (size_t k = 0; k < points.size(); ++k) {
      if (rect_l[k].x - rect_r[k].x <= 0)
        throw InputError(path, points[k].line, "u_right", "point " + points[k].name + " has no positive disparity");
      model.col(k) = calibration.rig.Triangulate(rect_l[k], rect_r[k]);
    }
    const Eigen::Matrix4d similarity = Eigen::umeyama(model, drawing, true);
    const double scale = std::cbrt(similarity.topLeftCorner<3, 3>().determinant());
    if (scale < 0.99 || scale > 1.01)
      throw InputError(
          path, 0, "x,y,z",
          cv::format("the drawing is %.4g times the triangulated size: coordinates must be metres", scale));
    fit.drawing_from_model = Rigid(Eigen::umeyama(model, drawing, false));
    for (size_t k = 0; k < points.size(); ++k)
      fit.residual_m.push_back((fit.drawing_from_model * Eigen::Vector3d(model.col(k)) - points[k].drawing).norm());
  } else {
    if (points.size() < 4) throw InputError(path, 0, "--object-frame", "with left pixels only, at least 4 points");
    std::vector<cv::Point3d> object;
    std::vector<cv::Point2d> image;
    for (const auto& p : points) {
      object.emplace_back(p.drawing.x(), p.drawing.y(), p.drawing.z());
      image.push_back(p.left_px);
    }
    cv::Mat rvec, tvec, rm;
    if (!cv::solvePnP(object, image, calibration.K1, calibration.D1, rvec, tvec, false, cv::SOLVEPNP_SQPNP))
      throw InputError(path, 0, "--object-frame", "no pose fits the points");
    cv::Rodrigues(rvec, rm);
    Rigid camera_from_drawing = Rigid::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) camera_from_drawing.linear()(r, c) = rm.at<double>(r, c);
      camera_from_drawing.translation()[r] = tvec.at<double>(r);
    }
    fit.drawing_from_model = camera_from_drawing.inverse();
    for (const auto& p : points) {
      // The reprojection error, as a distance at the point's depth.
      const Eigen::Vector3d c = camera_from_drawing * p.drawing;
      const cv::Point2d px = calibration.ProjectRaw(c, false);
      fit.residual_m.push_back(cv::norm(px - p.left_px) * c.z() / calibration.K1(0, 0));
    }
  }
  double sum = 0;
  size_t worst = 0;
  for (size_t k = 0; k < points.size(); ++k) {
    sum += fit.residual_m[k] * fit.residual_m[k];
    if (fit.residual_m[k] > fit.residual_m[worst]) worst = k;
  }
  fit.rms_m = std::sqrt(sum / points.size());
  if (fit.rms_m > max_rms_m)
    throw InputError(path, points[worst].line, points[worst].name,
                     cv::format("the points do not fit one rigid frame (RMS %.3f m; this point is off by %.3f m)",
                                fit.rms_m, fit.residual_m[worst]));
  return fit;
}

void MoveModel(ObjectModel* model, const Rigid& drawing_from_model) {
  const Eigen::Matrix3d r = drawing_from_model.linear();
  for (ModelPoint& p : model->points) {
    p.xyz = drawing_from_model * p.xyz;
    p.cov = r * p.cov * r.transpose();
  }
  for (auto& [name, pose] : model->views) pose = drawing_from_model * pose;
  model->frame = "drawing";
}

}  // namespace seamap
