#pragma once
// The options `seamap trajectory`, `build --refine-nav` and `replay
// --nav-mode` read for the pose source (core/controllers/pose_source.h).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "cli/args.h"
#include "core/camera/camera_model.h"
#include "core/controllers/pose_source.h"
#include "core/mosaic/build_config.h"
#include "core/mosaic/image_header.h"
#include "core/nav/frame_list.h"
#include "core/trajectory/survey_refiner.h"
#include "core/trajectory/trajectory_estimator.h"

namespace seamap::cli {

extern const char* kNavigationNoiseHelp;

// --nav-noise, --nav-drift, --heading-noise (and --threads) over the config's
// navigation.noise_m, drift_m_per_min, heading_noise_deg.
RefineOptions ReadRefineOptions(Args& args, const NavigationSettings& settings, int threads);

// The frame decoded whole for feature detection, or empty when it is missing,
// not a regular file, over max_pixels by its header, or unreadable.
cv::Mat ReadFrameForFeatures(const std::string& path, int64_t max_pixels = kDefaultMaxImagePixels);

}  // namespace seamap::cli
