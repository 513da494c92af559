#include "cli/trajectory_setup.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "core/image/image_read.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap::cli {

const char* kNavigationNoiseHelp =
    "  --nav-noise M       the navigation's white position noise, 1 sigma (default 0.05; config navigation.noise_m)\n"
    "  --nav-drift M_MIN   its drift rate, metres per minute (default 1; navigation.drift_m_per_min)\n"
    "  --heading-noise DEG its heading noise (default 1; navigation.heading_noise_deg)\n";

RefineOptions ReadRefineOptions(Args& args, const NavigationSettings& settings, int threads) {
  RefineOptions o;
  o.nav_noise_m = args.GetDouble("nav-noise", settings.noise_m);
  o.nav_drift_m_per_min = args.GetDouble("nav-drift", settings.drift_m_per_min);
  o.heading_noise_deg = args.GetDouble("heading-noise", settings.heading_noise_deg);
  o.threads = threads;
  o.Check();
  return o;
}

nlohmann::json RefineFrames(std::vector<FrameSpec>* frames, const CameraModel& camera, const RefineOptions& options,
                            bool quiet) {
  std::fprintf(stderr, "refining the navigation of %zu frames from the photos\n", frames->size());
  ProgressBar features("frames", static_cast<long>(frames->size()), !quiet);
  std::unique_ptr<ProgressBar> pairs;
  std::string stage = "features";
  RefineReport report;
  const std::vector<RefinedFrame> refined =
      RefineSurvey(*frames, camera, options, &report, [&](const std::string& now, int done, int total) {
        if (now == "features") {
          features.Update(done);
        } else if (now == "pairs") {
          if (!pairs) {
            features.Finish();
            pairs = std::make_unique<ProgressBar>("pairs", total, !quiet);
          }
          pairs->Update(done);
        }
        stage = now;
      });
  if (pairs) pairs->Finish();
  for (size_t i = 0; i < frames->size(); ++i) {
    FrameSpec& f = (*frames)[i];
    f.nav_pose = f.pose;
    f.pose = refined[i].pose;
  }
  nlohmann::json failures = nlohmann::json::object();
  for (const auto& [reason, count] : report.failures) failures[reason] = count;
  std::fprintf(stderr,
               "refine: %d of %d along-track and %d of %d cross-line pairs registered (median %.0f inliers), %d "
               "dropped by the pose graph; pair residual RMS %.1f mm -> %.1f mm; %d frames on navigation only; "
               "%.1f + %.1f + %.1f s\n",
               report.registered_along, report.pairs_along, report.registered_cross, report.pairs_cross,
               report.median_inliers, report.rejected_by_graph, report.residual_before_mm, report.residual_after_mm,
               report.nav_only, report.seconds_features, report.seconds_pairs, report.seconds_solve);
  nlohmann::json nav_only = nlohmann::json::array();
  for (size_t i = 0; i < refined.size(); ++i)
    if (refined[i].nav_only) nav_only.push_back((*frames)[i].image);
  return {{"frames", report.frames},
          {"frames_without_features", report.frames_without_features},
          {"pairs_along_track", report.pairs_along},
          {"pairs_cross_line", report.pairs_cross},
          {"registered_along_track", report.registered_along},
          {"registered_cross_line", report.registered_cross},
          {"rejected_by_pose_graph", report.rejected_by_graph},
          {"median_inliers", report.median_inliers},
          {"residual_before_mm", report.residual_before_mm},
          {"residual_after_mm", report.residual_after_mm},
          {"nav_only_frames", report.nav_only},
          {"nav_only", nav_only},
          {"registration_failures", failures},
          {"seconds",
           {{"features", report.seconds_features}, {"pairs", report.seconds_pairs}, {"solve", report.seconds_solve}}}};
}

EstimatorOptions EstimatorOptionsFrom(const std::string& mode, const RefineOptions& stated, const std::string& option) {
  EstimatorOptions o;
  o.mode = ParseEstimatorMode(mode, option);
  // Floors keep exact navigation from dividing by zero.
  o.nav_sigma_m = std::max(stated.nav_noise_m, 1e-3);
  o.filter.position_sigma_m = o.nav_sigma_m;
  o.filter.heading_noise_rad = std::max(stated.heading_noise_deg, 0.01) * M_PI / 180;
  return o;
}

void EstimatePose(TrajectoryEstimator* estimator, const CameraModel& camera, FrameSpec* frame) {
  if (!frame->time_s)
    throw InputError(frame->image_path, frame->nav_line, "time_s", "the navigation filter needs the frames' times");
  std::string problem;  // a frame without an image is placed by the filter's prediction
  const cv::Mat image = ReadGuardedImage(frame->image_path, &problem);
  std::optional<FrameFeatures> features;
  if (!image.empty()) features = DetectFeatures(image, camera, VoOptions{}.features);
  frame->nav_pose = frame->pose;
  frame->pose = estimator->Add(features ? &*features : nullptr, *frame->time_s, frame->pose);
}

}  // namespace seamap::cli
