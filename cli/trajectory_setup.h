#pragma once
// Estimating a survey's trajectory from its photos, shared by `seamap
// trajectory` and `seamap build --refine-nav`: the options the command line
// and the config give, a run with a progress bar, and its report as JSON.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "cli/args.h"
#include "core/camera/camera_model.h"
#include "core/mosaic/build_config.h"
#include "core/nav/frame_list.h"
#include "core/trajectory/survey_refiner.h"
#include "core/trajectory/trajectory_estimator.h"

namespace seamap::cli {

extern const char* kNavigationNoiseHelp;

// --nav-noise, --nav-drift, --heading-noise (and --threads) over the config's
// navigation.noise_m, drift_m_per_min, heading_noise_deg.
RefineOptions ReadRefineOptions(Args& args, const NavigationSettings& settings, int threads);

// Refines the frames' poses in place: FrameSpec::pose becomes the refined
// pose, FrameSpec::nav_pose keeps the navigation's. Returns the report as JSON.
nlohmann::json RefineFrames(std::vector<FrameSpec>* frames, const CameraModel& camera, const RefineOptions& options,
                            bool quiet);

// The navigation filter's options for `mode` ("vo" or "ekf"; InputError naming
// `option` otherwise), with the navigation's stated noise.
EstimatorOptions EstimatorOptionsFrom(const std::string& mode, const RefineOptions& stated, const std::string& option);

// Runs the filter on one frame as it arrives: reads its image, and places the
// frame where the filter says (FrameSpec::nav_pose keeps the navigation's).
// A frame whose image cannot be read is placed by the filter's prediction.
void EstimatePose(TrajectoryEstimator* estimator, const CameraModel& camera, FrameSpec* frame);

}  // namespace seamap::cli
