#pragma once
// The options `seamap trajectory`, `build --refine-nav` and `replay
// --nav-mode` read for the pose source (core/controllers/pose_source.h).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "cli/args.h"
#include "cli/enhance_setup.h"
#include "core/camera/camera_model.h"
#include "core/controllers/pose_source.h"
#include "core/mosaic/build_config.h"
#include "core/nav/frame_list.h"
#include "core/trajectory/survey_refiner.h"
#include "core/trajectory/trajectory_estimator.h"

namespace seamap::cli {

extern const char* kNavigationNoiseHelp;
extern const char* kFeatureEnhanceHelp;

// --nav-noise, --nav-drift, --heading-noise (and --threads) over the config's
// navigation.noise_m, drift_m_per_min, heading_noise_deg.
RefineOptions ReadRefineOptions(Args& args, const NavigationSettings& settings, int threads);

}  // namespace seamap::cli
