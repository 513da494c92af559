#pragma once
// Where each frame is placed before it is painted (FrameSpec::pose): the
// navigation as given; filtered from the photos as they arrive
// (TrajectoryEstimator, vo|ekf); or refined over the whole survey at once
// (RefineSurvey). A corrected pose keeps the navigation's in
// FrameSpec::nav_pose, so the mission keeps both tracks.
//
// The filter needs each photo decoded for its features. Live (Place), the
// decoded photo is handed back so the builder paints from it instead of
// reading the file again (MosaicBuilder::Push).
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/camera/camera_model.h"
#include "core/image/image_header.h"
#include "core/nav/frame_list.h"
#include "core/terrain/seabed_point.h"
#include "core/trajectory/feature_enhancement.h"
#include "core/trajectory/survey_refiner.h"
#include "core/trajectory/trajectory_estimator.h"

namespace seamap {

enum class PoseMode { kNavigation, kFilter, kRefine };

struct PoseSourceOptions {
  PoseMode mode = PoseMode::kNavigation;
  EstimatorOptions filter;  // kFilter
  RefineOptions refine;     // kRefine
  // Seed 004's chain in front of the features of kFilter and kRefine (a
  // whole survey: PlaceSurvey); off by default.
  FeatureEnhanceOptions feature_enhance;
  int threads = 0;  // feature detection of a whole survey (0: one per core)
  // Photos whose header claims more pixels are not decoded (the build's max_image_pixels).
  int64_t max_image_pixels = kDefaultMaxImagePixels;
  bool quiet = false;  // no progress bars
  void Check() const;
};

// The navigation filter's options for `mode` ("vo" or "ekf"; InputError naming
// `option` otherwise), with the navigation's stated noise.
EstimatorOptions EstimatorOptionsFrom(const std::string& mode, const RefineOptions& stated, const std::string& option);

class PoseSource {
 public:
  PoseSource(const CameraModel& camera, PoseSourceOptions options);
  ~PoseSource();

  // "nav", "vo", "ekf" or "refine".
  std::string name() const;
  PoseMode mode() const { return options_.mode; }

  // The whole survey at once (build --refine-nav, seamap trajectory): places
  // every frame, with a progress bar and a summary line on stderr. Returns
  // the run's report as JSON (null for the navigation); `flags` gets, frame
  // by frame, "" or ';'-separated words: refine's "nav_only" (no pair placed
  // it), with "no_image" (unreadable or refused: too large), "no_texture"
  // (uniform), "identical_photos" (a pair refused as one photo twice: a
  // frozen camera); the filter's "no_image", "low_texture" (no visual
  // odometry from it: the position is the filter's prediction),
  // "restart_after_gap". A frame refine left where the navigation put it
  // keeps no separate navigation pose (FrameSpec::nav_pose): the mission
  // does not count it as corrected.
  nlohmann::json PlaceSurvey(std::vector<FrameSpec>* frames, std::vector<std::string>* flags = nullptr);

  // One frame as it arrives (replay --nav-mode): places it where the filter
  // says (a frame whose photo cannot be read: the filter's prediction).
  // Returns the photo when it was decoded for that (empty otherwise).
  // InputError naming the frame's time_s when it has none.
  cv::Mat Place(FrameSpec* frame);

  // The seabed points the last refine triangulated (refine's bundle method; empty otherwise).
  const SeabedPoints& seabed_points() const { return seabed_points_; }

 private:
  // Settles feature_enhance (auto: tried on the first frames) into the
  // features' options; what it chose and measured, for the report.
  nlohmann::json ChooseEnhancement(const std::vector<FrameSpec>& frames);
  nlohmann::json Refine(std::vector<FrameSpec>* frames, std::vector<std::string>* flags);
  nlohmann::json Filter(std::vector<FrameSpec>* frames, std::vector<std::string>* flags);

  CameraModel camera_;
  PoseSourceOptions options_;
  std::unique_ptr<TrajectoryEstimator> live_;  // Place's filter
  SeabedPoints seabed_points_;
};

}  // namespace seamap
