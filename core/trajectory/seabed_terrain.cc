#include "core/trajectory/seabed_terrain.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <future>
#include <memory>

#include "core/camera/frame_projector.h"
#include "core/image/image_read.h"
#include "core/util/statistics.h"
#include "core/util/thread_pool.h"

namespace seamap {
namespace {

using Clock = std::chrono::steady_clock;
constexpr size_t kProblemsKept = 10;

double Since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// A frame's features from its image; empty with *problem when unusable.
FrameFeatures FeaturesFromImage(const FrameSpec& f, const CameraModel& camera, const FeatureOptions& options,
                                int64_t max_image_pixels, std::string* problem) {
  const cv::Mat image = ReadGuardedImage(f.image_path, problem, max_image_pixels);
  if (image.empty()) return {};
  if (std::abs(image.cols * camera.height - image.rows * camera.width) > std::max(image.cols, camera.width)) {
    *problem = "image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) + ", not the camera's shape";
    return {};
  }
  return DetectFeatures(image, camera, options);
}

// A footprint scaled about its centre as if the seabed were `relief_m` further down.
std::array<LocalXY, 4> Widened(const std::array<LocalXY, 4>& corners, const VehiclePose& pose, double relief_m) {
  const double scale = std::min(3.0, (pose.altitude_m + relief_m) / std::max(pose.altitude_m, 1e-3));
  LocalXY centre;
  for (const LocalXY& p : corners) {
    centre.east += p.east / 4;
    centre.north += p.north / 4;
  }
  std::array<LocalXY, 4> out;
  for (int k = 0; k < 4; ++k)
    out[k] = {centre.east + scale * (corners[k].east - centre.east),
              centre.north + scale * (corners[k].north - centre.north)};
  return out;
}

// Where the rays of the image border meet the fitted surface: each ray's
// height found by a few fixed-point steps; where the grid has no height
// there, the last height along the ray before it.
std::vector<LocalXY> FootprintOnGrid(const CameraModel& camera, const VehiclePose& pose, const HeightGrid& grid) {
  constexpr int kPerSide = 4;
  const double w = camera.width, h = camera.height;
  std::vector<cv::Point2d> border;
  for (int k = 0; k < kPerSide; ++k) border.push_back({-0.5 + (w * k) / kPerSide, -0.5});
  for (int k = 0; k < kPerSide; ++k) border.push_back({w - 0.5, -0.5 + (h * k) / kPerSide});
  for (int k = 0; k < kPerSide; ++k) border.push_back({w - 0.5 - (w * k) / kPerSide, h - 0.5});
  for (int k = 0; k < kPerSide; ++k) border.push_back({-0.5, h - 0.5 - (h * k) / kPerSide});
  const std::vector<cv::Point2d> ideal = camera.Undistort(border);
  const TrackCamera view = TrackCameraOf(camera, pose);
  std::vector<LocalXY> out;
  for (const cv::Point2d& px : ideal) {
    const Eigen::Vector3d ray =
        view.world_from_camera * Eigen::Vector3d((px.x - camera.cx) / camera.fx, (px.y - camera.cy) / camera.fy, 1);
    if (!(ray.z() < -1e-3)) continue;
    double up = view.seabed_up_m;
    for (int step = 0; step < 5; ++step) {
      const double t = (up - view.centre_m.z()) / ray.z();
      if (!(t > 0)) break;
      double sampled = 0;
      bool found = false;
      for (int back = 0; back <= 20 && !found; ++back) {  // back along the ray, 5 % of the range a step
        const Eigen::Vector3d p = view.centre_m + t * (1 - 0.05 * back) * ray;
        found = grid.Sample({p.x(), p.y()}, &sampled);
      }
      if (!found) break;
      up = sampled;
    }
    const double t = (up - view.centre_m.z()) / ray.z();
    if (t > 0) out.push_back({view.centre_m.x() + t * ray.x(), view.centre_m.y() + t * ray.y()});
  }
  return out;
}

}  // namespace

void TerrainOptions::Check() const {
  features.Check();
  tracks.Check();
  fit.Check();
}

HeightGrid FitSeabedTerrain(const SeabedPoints& points, const std::vector<VehiclePose>& poses,
                            const CameraModel& camera, const HeightFitOptions& options, double max_relief_m,
                            HeightFitReport* report) {
  options.Check();
  HeightFitReport local;
  HeightFitReport* fit_report = report ? report : &local;
  // Fitted within the footprints on the expected seabed widened by the relief
  // allowed, then clipped to the footprints on the fitted surface.
  std::vector<std::array<LocalXY, 4>> wide_swath;
  std::vector<double> altitudes;
  bool has_depth = false;
  for (const VehiclePose& p : poses) {
    has_depth |= p.depth_m != 0;
    altitudes.push_back(p.altitude_m);
    if (auto corners = Footprint(camera, p)) wide_swath.push_back(Widened(*corners, p, max_relief_m));
  }
  HeightFitOptions fit = options;
  if (fit.gsd_m <= 0 && !altitudes.empty()) fit.gsd_m = GroundSampleDistance(camera, Median(altitudes));
  HeightGrid grid = FitHeightGrid(points, wide_swath, has_depth, fit, fit_report);
  if (!grid.empty()) {
    std::vector<std::vector<LocalXY>> swath;
    for (const VehiclePose& p : poses)
      if (Footprint(camera, p)) swath.push_back(FootprintOnGrid(camera, p, grid));
    ClipHeightGrid(swath, &grid, fit_report);
  }
  return grid;
}

HeightGrid EstimateSeabedTerrainFromFeatures(const std::vector<VehiclePose>& poses, const CameraModel& camera,
                                             const FeatureSource& features, const TerrainOptions& options,
                                             TerrainReport* report, const TerrainProgress& progress,
                                             SeabedTracks* tracks_out) {
  options.tracks.Check();
  options.fit.Check();
  TerrainReport r;
  r.frames = static_cast<int>(poses.size());
  auto start = Clock::now();
  SeabedTracks tracks = BuildSeabedTracks(poses, camera, features, options.tracks, &r.tracks, [&](int done, int total) {
    if (progress) progress("tracks", done, total);
  });
  r.seconds_features_and_tracks = Since(start);

  start = Clock::now();
  HeightGrid grid;
  if (options.extra_points.empty()) {
    grid = FitSeabedTerrain(tracks.points, poses, camera, options.fit, options.tracks.max_relief_m, &r.fit);
  } else {
    SeabedPoints all = tracks.points;
    all.insert(all.end(), options.extra_points.begin(), options.extra_points.end());
    grid = FitSeabedTerrain(all, poses, camera, options.fit, options.tracks.max_relief_m, &r.fit);
  }
  r.seconds_fit = Since(start);
  if (progress) progress("fit", 1, 1);
  if (tracks_out) *tracks_out = std::move(tracks);
  if (report) {  // what the image readers counted stays
    r.frames_unreadable = report->frames_unreadable;
    r.problems = std::move(report->problems);
    *report = std::move(r);
  }
  return grid;
}

HeightGrid EstimateSeabedTerrain(const std::vector<FrameSpec>& frames, const CameraModel& camera,
                                 const TerrainOptions& options, TerrainReport* report, const TerrainProgress& progress,
                                 SeabedTracks* tracks) {
  options.Check();
  // Features a few frames ahead on the pool; the tracks take them in order.
  // (The queue outlives the pool: queued jobs write into it.)
  struct Pending {
    std::future<FrameFeatures> features;
    std::string problem;
  };
  std::deque<std::unique_ptr<Pending>> pending;
  ThreadPool pool(options.threads);
  const size_t ahead = static_cast<size_t>(std::max(2, 2 * pool.size()));
  size_t next = 0;
  TerrainReport local;
  TerrainReport* r = report ? report : &local;
  r->frames_unreadable = 0;
  r->problems.clear();
  auto submit = [&] {
    while (next < frames.size() && pending.size() < ahead) {
      auto p = std::make_unique<Pending>();
      Pending* raw = p.get();
      const FrameSpec* f = &frames[next++];
      p->features = pool.Submit([f, raw, &camera, &options] {
        return FeaturesFromImage(*f, camera, options.features, options.max_image_pixels, &raw->problem);
      });
      pending.push_back(std::move(p));
    }
  };
  const FeatureSource source = [&](int frame) {
    submit();
    std::unique_ptr<Pending> p = std::move(pending.front());
    pending.pop_front();
    FrameFeatures features = p->features.get();
    if (!p->problem.empty()) {
      ++r->frames_unreadable;
      if (r->problems.size() < kProblemsKept) r->problems.push_back(frames[frame].image + ": " + p->problem);
    }
    submit();
    return features;
  };
  std::vector<VehiclePose> poses;
  poses.reserve(frames.size());
  for (const FrameSpec& f : frames) poses.push_back(f.pose);
  // BuildSeabedTracks asks only for frames whose footprint sees the seabed:
  // keep the queue aligned by taking the others' features and dropping them.
  int cursor = 0;
  const FeatureSource in_order = [&](int frame) {
    FrameFeatures features;
    while (cursor <= frame) {
      features = source(cursor);
      ++cursor;
    }
    return features;
  };
  return EstimateSeabedTerrainFromFeatures(poses, camera, in_order, options, r, progress, tracks);
}

}  // namespace seamap
