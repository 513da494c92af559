#pragma once
// The seabed's shape from the photos: the one entry point `build --terrain`
// calls. Features of every frame (frame_features.h, on a thread pool, a few
// frames ahead), seabed tracks triangulated with the frames' poses
// (seabed_tracks.h), and the height model fitted to them (height_fit.h)
// over the surveyed swath (the frames' footprints on the expected seabed).
// Heights are metres up, relative to the sea surface when the navigation
// has depth (some frame with depth_m != 0), else to the vehicle's depth 0.
#include <functional>
#include <string>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/image/image_header.h"
#include "core/nav/frame_list.h"
#include "core/terrain/height_fit.h"
#include "core/terrain/height_grid.h"
#include "core/terrain/seabed_point.h"
#include "core/trajectory/frame_features.h"
#include "core/trajectory/seabed_tracks.h"

namespace seamap {

struct TerrainOptions {
  FeatureOptions features;
  TrackOptions tracks;
  HeightFitOptions fit;  // fit.gsd_m 0: the camera's at the median altitude
  int threads = 0;       // feature detection; 0: one per core
  // Photos whose header claims more pixels are not decoded (the build's max_image_pixels).
  int64_t max_image_pixels = kDefaultMaxImagePixels;
  // Points from elsewhere fitted with the tracks' (a stereo rig's pairs,
  // core/stereo/stereo_seabed_points.h; build --terrain-points), same datum.
  SeabedPoints extra_points;
  void Check() const;  // InputError naming the option
};

struct TerrainReport {
  int frames = 0;
  int frames_unreadable = 0;  // no image, wrong shape, or no seabed in view
  TrackReport tracks;
  HeightFitReport fit;
  double seconds_features_and_tracks = 0, seconds_fit = 0;
  std::vector<std::string> problems;  // the first few unreadable frames: "image: why"
};

// progress(stage, done, total): stage "tracks" per frame, then "fit" once.
using TerrainProgress = std::function<void(const std::string& stage, int done, int total)>;

// frames: in acquisition order, with their poses (navigation or refined).
// The grid is empty when no seabed point could be triangulated. `tracks`,
// when given, receives the triangulated tracks (for a bundle adjustment).
HeightGrid EstimateSeabedTerrain(const std::vector<FrameSpec>& frames, const CameraModel& camera,
                                 const TerrainOptions& options, TerrainReport* report,
                                 const TerrainProgress& progress = nullptr, SeabedTracks* tracks = nullptr);

// The height model fitted to seabed points triangulated elsewhere (the
// bundle adjustment's, PoseSource::seabed_points()) over the swath of
// `poses`, as EstimateSeabedTerrain fits its own: no photo is read.
// max_relief_m: how far the swath is widened (TrackOptions::max_relief_m).
HeightGrid FitSeabedTerrain(const SeabedPoints& points, const std::vector<VehiclePose>& poses,
                            const CameraModel& camera, const HeightFitOptions& options, double max_relief_m,
                            HeightFitReport* report = nullptr);

// The same from features a caller already has (or a test makes), one frame
// at a time in order; options.features and options.threads are not used.
HeightGrid EstimateSeabedTerrainFromFeatures(const std::vector<VehiclePose>& poses, const CameraModel& camera,
                                             const FeatureSource& features, const TerrainOptions& options,
                                             TerrainReport* report, const TerrainProgress& progress = nullptr,
                                             SeabedTracks* tracks = nullptr);

}  // namespace seamap
