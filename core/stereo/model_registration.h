#pragma once
// One stereo pair against the model: the working left keypoints matched to
// the descriptors of every model view (ratio test against the best match of
// another point, a model point counted once), a RANSAC over 3-point rigid
// fits of the 3D-3D matches (cv::solvePnPRansac when fewer than 6 have a
// stereo partner) scored by stereo reprojection, then a refinement of the
// stereo reprojection errors with the model points free under their priors.
#include <string>
#include <vector>

#include "core/stereo/object_model.h"
#include "core/stereo/stereo_bundle.h"
#include "core/stereo/stereo_matcher.h"

namespace seamap {

// (Not RegistrationOptions: core/trajectory/pair_registration.h has that name in
// this namespace, and two classes of one name break the one-definition rule.)
struct ModelRegistrationOptions {
  double ratio = 0.8;
  double inlier_px = 2;  // reprojection in both images
  int ransac_iterations = 2000;
  uint64_t seed = 1;
};

struct ModelMatch {
  int point = -1;  // model point
  int left = -1;   // working left keypoint
  float distance = 0;
};

struct Registration {
  bool ok = false;
  std::string failure;
  Rigid object_from_camera = Rigid::Identity();
  std::vector<ModelMatch> matches;
  std::vector<int> inliers;  // indices into matches
  int matches_3d = 0;
  double rms_px = 0;
  int model_views_matched = 0;
  double seconds = 0;
};

std::vector<ModelMatch> MatchToModel(const ObjectModel& model, const ImageFeatures& left, double ratio);

Registration RegisterPair(const ObjectModel& model, const StereoFrame& frame, const RectifiedRig& rig,
                          const ModelRegistrationOptions& options);

// Reprojection error (px, the larger of left and right) of a model point matched to a working keypoint.
double MatchError(const ObjectModel& model, const StereoFrame& frame, const RectifiedRig& rig, const ModelMatch& m,
                  const Rigid& object_from_camera);

}  // namespace seamap
