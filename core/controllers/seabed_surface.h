#pragma once
// The height model a build paints onto (build --terrain, --terrain-file; the
// config's "terrain"): read from a file, or estimated from the photos once
// the frames' poses are placed. One call, before the first frame is painted.
#include <memory>
#include <string>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/geo/local_frame.h"
#include "core/image/image_header.h"
#include "core/mosaic/build_config.h"
#include "core/nav/frame_list.h"
#include "core/terrain/height_grid.h"
#include "core/terrain/seabed_point.h"

namespace seamap {

struct SeabedSurface {
  std::shared_ptr<const HeightGrid> grid;  // null: flat (no terrain asked for)
  // What the frames are painted onto (core/terrain/painting_surface.h):
  // `grid` with its holes near known cells filled by continuing its surface,
  // on finer cells; the mission keeps `grid` as it is.
  std::shared_ptr<const HeightGrid> painted;
  std::string source;  // "file DEM.tif" or "estimated from the photos"
  std::string path;    // the file read ("" when estimated)
  // Share of the frames' footprint samples (centre and corners on the plane)
  // where the model has no height: painted on the frame's own plane there.
  double hole_share = 0;
  double painted_hole_share = 0;  // the same for `painted`: where the frame's own plane stands in
  int painted_refine = 1;         // painted cells per model cell along each axis
  // Median of (the model's height - the navigation's seabed height,
  // -(depth_m + altitude_m)) below the frames: how far the model is off the
  // seabed the navigation measures (0 on the same vertical datum).
  double datum_offset_m = 0;
  std::string Summary() const;  // one line for the build's output
};

// A height model's file (--terrain-file; GeoTIFF or any GDAL raster, any
// CRS) in the mission's local frame: only the part around the frames'
// footprints (a large DEM around a small survey stays small in memory).
// InputError naming the file.
SeabedSurface ReadSeabedSurface(const std::string& path, const LocalFrame& frame, const CameraModel& camera,
                                const std::vector<FrameSpec>& frames);

// The seabed estimated from the photos of `frames` (poses placed: refined
// first with --refine-nav). InputError naming --terrain.
// Photos whose header claims more than max_image_pixels are not decoded.
// bundle_points: the seabed points the refinement's bundle adjustment
// triangulated with these poses (PoseSource::seabed_points()); with
// settings.from_bundle the model is fitted to them and no photo is read.
SeabedSurface EstimateSeabedSurface(const LocalFrame& frame, const CameraModel& camera,
                                    const std::vector<FrameSpec>& frames, const TerrainSettings& settings, int threads,
                                    bool show_progress, int64_t max_image_pixels = kDefaultMaxImagePixels,
                                    const SeabedPoints* bundle_points = nullptr);

// The share of footprint samples without a height (see SeabedSurface::hole_share).
double HoleShare(const HeightGrid& grid, const CameraModel& camera, const std::vector<FrameSpec>& frames);

// Sets painted, hole_share, painted_hole_share and datum_offset_m for `frames`. A model far off the
// seabed the navigation measures (more than 1 m and half the median
// altitude: another vertical datum, or another site) is an InputError
// naming `option`; one that covers none of the frames too.
void CheckAgainstNavigation(const CameraModel& camera, const std::vector<FrameSpec>& frames, const std::string& option,
                            SeabedSurface* surface);

}  // namespace seamap
