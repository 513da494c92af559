#include "core/controllers/pose_source.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <future>
#include <set>

#include "core/image/image_read.h"
#include "core/util/error.h"
#include "core/util/progress.h"
#include "core/util/thread_pool.h"

namespace seamap {
namespace {

// Whether refine moved a frame from its navigation pose (beyond rounding).
bool Moved(const VehiclePose& nav, const VehiclePose& refined) {
  const auto differ = [](double a, double b) { return !(std::fabs(a - b) <= 1e-9 * std::max(1.0, std::fabs(a))); };
  return differ(nav.east_m, refined.east_m) || differ(nav.north_m, refined.north_m) ||
         differ(nav.depth_m, refined.depth_m) || differ(nav.altitude_m, refined.altitude_m) ||
         std::fabs(std::remainder(nav.heading_deg - refined.heading_deg, 360.0)) > 1e-9 ||
         differ(nav.pitch_deg, refined.pitch_deg) || differ(nav.roll_deg, refined.roll_deg);
}

}  // namespace

void PoseSourceOptions::Check() const {
  feature_enhance.Check();
  if (mode == PoseMode::kFilter) filter.Check();
  if (mode == PoseMode::kRefine) refine.Check();
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

PoseSource::PoseSource(const CameraModel& camera, PoseSourceOptions options)
    : camera_(camera), options_(std::move(options)) {
  options_.refine.max_image_pixels = options_.max_image_pixels;
  options_.Check();
  if (options_.mode == PoseMode::kFilter) live_ = std::make_unique<TrajectoryEstimator>(camera_, options_.filter);
}

PoseSource::~PoseSource() = default;

std::string PoseSource::name() const {
  switch (options_.mode) {
    case PoseMode::kNavigation:
      return "nav";
    case PoseMode::kRefine:
      return "refine";
    case PoseMode::kFilter:
      break;
  }
  return options_.filter.mode == EstimatorMode::kVo ? "vo" : "ekf";
}

nlohmann::json PoseSource::PlaceSurvey(std::vector<FrameSpec>* frames, std::vector<std::string>* flags) {
  if (flags) flags->assign(frames->size(), "");
  if (options_.mode == PoseMode::kNavigation) return nullptr;
  const nlohmann::json enhancement = ChooseEnhancement(*frames);
  nlohmann::json report = options_.mode == PoseMode::kRefine ? Refine(frames, flags) : Filter(frames, flags);
  if (!enhancement.is_null()) report["feature_enhance"] = enhancement;
  return report;
}

nlohmann::json PoseSource::ChooseEnhancement(const std::vector<FrameSpec>& frames) {
  const FeatureEnhanceOptions& o = options_.feature_enhance;
  if (o.spec == "off") return nullptr;
  // The probe: the first readable frames (also the flat field's seed).
  std::vector<cv::Mat> probe;
  for (size_t i = 0; i < frames.size() && static_cast<int>(probe.size()) < o.probe_frames; ++i) {
    std::string problem;
    cv::Mat image = ReadGuardedImage(frames[i].image_path, &problem, options_.max_image_pixels);
    if (!image.empty()) probe.push_back(image);
  }
  FeatureOptions& features =
      options_.mode == PoseMode::kRefine ? options_.refine.features : options_.filter.vo.features;
  const EnhancementChoice choice = ChooseFeatureEnhancement(o, probe, camera_, features);
  features.enhance = choice.chain;
  nlohmann::json trials = nlohmann::json::array();
  for (const auto& t : choice.trials)
    trials.push_back({{"chain", t.chain}, {"inliers_per_pair", t.inliers}, {"features_per_frame", t.features}});
  std::fprintf(stderr, "feature enhancement (%s): %s\n", o.spec.c_str(), choice.chain.Names().c_str());
  for (const auto& t : choice.trials)
    std::fprintf(stderr, "  %-40s %7.1f inliers/pair %7.1f features/frame\n", t.chain.c_str(), t.inliers, t.features);
  return {{"requested", o.spec}, {"chain", choice.chain.Names()}, {"trials", trials}};
}

cv::Mat PoseSource::Place(FrameSpec* frame) {
  if (options_.mode != PoseMode::kFilter) return cv::Mat();
  if (!frame->time_s)
    throw InputError(frame->image_path, frame->nav_line, "time_s", "the navigation filter needs the frames' times");
  std::string problem;  // a frame without an image is placed by the filter's prediction
  cv::Mat image = ReadGuardedImage(frame->image_path, &problem, options_.max_image_pixels);
  std::optional<FrameFeatures> features;
  // The replay's filter has always detected with the default feature settings.
  if (!image.empty()) features = DetectFeatures(image, camera_, VoOptions{}.features);
  frame->nav_pose = frame->pose;
  frame->pose = live_->Add(features ? &*features : nullptr, *frame->time_s, frame->pose);
  return image;
}

nlohmann::json PoseSource::Refine(std::vector<FrameSpec>* frames, std::vector<std::string>* flags) {
  std::fprintf(stderr, "refining the navigation of %zu frames from the photos\n", frames->size());
  ProgressBar features("frames", static_cast<long>(frames->size()), !options_.quiet);
  std::unique_ptr<ProgressBar> pairs, windows;
  RefineReport report;
  const std::vector<RefinedFrame> refined = RefineSurvey(
      *frames, camera_, options_.refine, &report,
      [&](const std::string& now, int done, int total) {
        if (now == "features") {
          features.Update(done);
        } else if (now == "pairs") {
          if (!pairs) {
            features.Finish();
            pairs = std::make_unique<ProgressBar>("pairs", total, !options_.quiet);
          }
          pairs->Update(done);
        } else if (now == "bundle" && total > 1) {  // the bundle's windows (windowed_bundle.h), when several
          if (!windows) windows = std::make_unique<ProgressBar>("bundle windows", total, !options_.quiet);
          windows->Update(done);
        }
      },
      &seabed_points_);
  if (pairs) pairs->Finish();
  if (windows) windows->Finish();
  int corrected = 0;
  for (size_t i = 0; i < frames->size(); ++i) {
    FrameSpec& f = (*frames)[i];
    // Only a pose refine moved is a correction; the others stay the navigation's.
    if (Moved(f.pose, refined[i].pose)) {
      f.nav_pose = f.pose;
      ++corrected;
    }
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
  // Why frames gave no features, the first few by name (a survey of black frames says so once).
  int problems = 0, still = 0;
  for (size_t i = 0; i < refined.size(); ++i) {
    still += refined[i].still_photos;
    if (refined[i].problem.empty()) continue;
    if (++problems <= 5)
      std::fprintf(stderr, "refine: %s: %s\n", (*frames)[i].image.substr(0, 100).c_str(), refined[i].problem.c_str());
  }
  if (problems > 5) std::fprintf(stderr, "refine: %d more frames without features\n", problems - 5);
  if (still)
    std::fprintf(stderr,
                 "refine: %d frames are the same photo as a neighbour (identical frames, or no parallax while the "
                 "navigation moved: a frozen camera?); their pairs were refused\n",
                 still);
  std::fprintf(stderr, "refine: poses corrected in %d of %zu frames; the others keep the navigation's\n", corrected,
               frames->size());
  if (!report.method_note.empty()) std::fprintf(stderr, "refine: %s\n", report.method_note.c_str());
  if (report.bundle)
    std::fprintf(stderr,
                 "refine: bundle adjustment of %d seabed points (%d observations, %d dropped), reprojection RMS "
                 "%.2f px -> %.2f px; %.1f s\n",
                 report.points, report.observations, report.observations_rejected, report.reprojection_before_px,
                 report.reprojection_after_px, report.seconds_bundle);
  nlohmann::json nav_only = nlohmann::json::array();
  std::set<std::string> nav_only_images;  // flagged by name, as the report lists them
  for (size_t i = 0; i < refined.size(); ++i)
    if (refined[i].nav_only) {
      nav_only.push_back((*frames)[i].image);
      nav_only_images.insert((*frames)[i].image);
    }
  // Frames refine could not use, by why: one by one in the CSV (`flags`),
  // counted with their first names in the report the mission keeps.
  nlohmann::json flagged = nlohmann::json::object();
  constexpr size_t kNamesPerFlag = 1000;
  for (size_t i = 0; i < frames->size(); ++i) {
    std::vector<std::string> words;
    if (nav_only_images.count((*frames)[i].image)) words.push_back("nav_only");
    const std::string& problem = refined[i].problem;
    if (problem.rfind("no texture", 0) == 0)
      words.push_back("no_texture");
    else if (problem.rfind("missing image", 0) == 0 || problem.rfind("not a regular file", 0) == 0 ||
             problem.rfind("image too large", 0) == 0 || problem.rfind("unreadable image", 0) == 0)
      words.push_back("no_image");
    if (refined[i].still_photos) words.push_back("identical_photos");
    for (const auto& w : words) {
      if (w == "nav_only") continue;  // the mission's frames say which: no navigation pose beside theirs
      nlohmann::json& entry = flagged[w];
      if (entry.is_null()) entry = {{"frames", 0}, {"images", nlohmann::json::array()}};
      entry["frames"] = entry["frames"].get<int>() + 1;
      if (entry["images"].size() < kNamesPerFlag) entry["images"].push_back((*frames)[i].image);
    }
    if (!flags) continue;
    std::string& flag = (*flags)[i];
    for (const auto& w : words) flag += (flag.empty() ? "" : ";") + w;
  }
  const nlohmann::json relief = report.navigated_relief_m ? nlohmann::json(*report.navigated_relief_m) : nullptr;
  return {{"frames", report.frames},
          {"corrected_frames", corrected},
          {"flagged_frames", flagged},
          {"identical_photo_frames", still},
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
          {"method", report.bundle ? "bundle" : "planar"},
          {"navigated_relief_m", relief},
          {"method_note", report.method_note},
          {"bundle",
           {{"points", report.points},
            {"observations", report.observations},
            {"observations_rejected", report.observations_rejected},
            {"tracks_spread", report.tracks_spread},
            {"reprojection_before_px", report.reprojection_before_px},
            {"reprojection_after_px", report.reprojection_after_px},
            {"linear_solver", report.bundle_solver},
            {"iterations", report.bundle_iterations},
            {"windows", report.bundle_windows},
            {"seam_jump_max_mm", report.bundle_seam_jump_max_mm},
            {"seam_jump_median_mm", report.bundle_seam_jump_median_mm},
            {"window_solved_frames_max", report.bundle_window_solved_frames_max},
            {"window_held_frames_max", report.bundle_window_held_frames_max},
            {"window_cpu_s_max", report.bundle_window_cpu_s_max},
            {"window_cpu_s_median", report.bundle_window_cpu_s_median},
            {"window_start_rms_px_max", report.bundle_window_start_rms_px_max}}},
          {"peak_feature_mb", report.peak_feature_bytes / 1e6},
          {"seconds",
           {{"features", report.seconds_features},
            {"pairs", report.seconds_pairs},
            {"solve", report.seconds_solve},
            {"bundle", report.seconds_bundle}}}};
}

// Features on the pool, a bounded stretch ahead; the filter in order.
nlohmann::json PoseSource::Filter(std::vector<FrameSpec>* frames_in, std::vector<std::string>* flags) {
  std::vector<FrameSpec>& frames = *frames_in;
  for (const FrameSpec& f : frames)
    if (!f.time_s) throw InputError(f.image_path, f.nav_line, "time_s", "vo and ekf need the navigation's times");
  const EstimatorOptions& options = options_.filter;
  ThreadPool pool(options_.threads);
  TrajectoryEstimator estimator(camera_, options);
  ProgressBar progress("frames", static_cast<long>(frames.size()), !options_.quiet);
  struct Read {
    std::optional<FrameFeatures> features;
    std::string problem;  // why there are none
  };
  std::deque<std::future<Read>> ahead;
  std::vector<std::string> problems;  // "image: why", the first few
  size_t next = 0;
  const size_t depth = 4 * static_cast<size_t>(pool.size());
  const auto start = std::chrono::steady_clock::now();
  int unreadable = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    for (; next < frames.size() && next < i + depth; ++next)
      ahead.push_back(pool.Submit([&, next]() -> Read {
        Read read;
        const cv::Mat image = ReadGuardedImage(frames[next].image_path, &read.problem, options_.max_image_pixels);
        if (!image.empty()) read.features = DetectFeatures(image, camera_, options.vo.features);
        return read;
      }));
    const Read read = ahead.front().get();
    ahead.pop_front();
    const std::optional<FrameFeatures>& features = read.features;
    unreadable += !features;
    if (!features && problems.size() < 5) problems.push_back(frames[i].image.substr(0, 100) + ": " + read.problem);
    const VehiclePose pose = estimator.Add(features ? &*features : nullptr, *frames[i].time_s, frames[i].pose);
    frames[i].nav_pose = frames[i].pose;
    frames[i].pose = pose;
    if (flags) {
      std::string& flag = (*flags)[i];
      flag = features ? "" : "no_image";
      if (!estimator.last_flags().empty()) flag += (flag.empty() ? "" : ";") + estimator.last_flags();
    }
    progress.Update(static_cast<long>(i + 1));
  }
  progress.Finish();
  for (const std::string& problem : problems) std::fprintf(stderr, "%s: %s\n", name().c_str(), problem.c_str());
  if (unreadable > static_cast<int>(problems.size()))
    std::fprintf(stderr, "%s: %d more frames unread\n", name().c_str(), unreadable - static_cast<int>(problems.size()));
  nlohmann::json gaps = nlohmann::json::array();
  for (const auto& [time_s, gap_s] : estimator.gaps()) {
    if (gaps.size() == 5)
      std::fprintf(stderr, "%s: %zu more restarts after gaps\n", name().c_str(), estimator.gaps().size() - 5);
    if (gaps.size() < 5)
      std::fprintf(stderr,
                   "%s: the navigation's time jumps by %.6g s before the frame at time_s %.10g (limit %.6g s): the "
                   "filter restarted there from the navigation\n",
                   name().c_str(), gap_s, time_s, options.max_gap_s);
    gaps.push_back({{"time_s", time_s}, {"gap_s", gap_s}});
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto& vo = estimator.vo_counts();
  const auto& filter = estimator.filter_counts();
  std::fprintf(stderr,
               "%s: %d VO measurements (%d homography, %d essential, %d hover), %d pairs failed, %d low-texture "
               "frames, %d identical to the last; filter took %d, gated %d VO updates (mean NIS %.2f), %d "
               "re-acquisitions; %.1f frames/s\n",
               options.mode == EstimatorMode::kVo ? "vo" : "ekf", vo.measurements, vo.homography, vo.essential,
               vo.hover, vo.failed_pairs, vo.low_texture, vo.identical, filter.velocity_accepted,
               filter.velocity_rejected,
               filter.velocity_accepted ? filter.velocity_nis_sum / filter.velocity_accepted : 0.0,
               filter.reacquisitions, frames.size() / std::max(seconds, 1e-9));
  return {{"frames", frames.size()},
          {"unreadable_frames", unreadable},
          {"vo_measurements", vo.measurements},
          {"homography", vo.homography},
          {"essential", vo.essential},
          {"hover", vo.hover},
          {"failed_pairs", vo.failed_pairs},
          {"mean_motion_inliers", vo.homography + vo.essential > 0
                                      ? static_cast<double>(vo.motion_inliers) / (vo.homography + vo.essential)
                                      : 0.0},
          {"low_texture_frames", vo.low_texture},
          {"missing_altitude", vo.missing_altitude},
          {"identical_frames", vo.identical},
          {"velocity_accepted", filter.velocity_accepted},
          {"velocity_rejected", filter.velocity_rejected},
          {"mean_vo_nis", filter.velocity_accepted ? filter.velocity_nis_sum / filter.velocity_accepted : 0.0},
          {"depth_rejected", filter.depth_rejected},
          {"position_accepted", filter.position_accepted},
          {"position_rejected", filter.position_rejected},
          {"reacquisitions", filter.reacquisitions},
          {"restarts_after_gap", gaps},
          {"max_gap_s", options.max_gap_s},
          {"seconds", seconds},
          {"frames_per_s", frames.size() / std::max(seconds, 1e-9)}};
}

}  // namespace seamap
