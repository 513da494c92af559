#include "core/controllers/seabed_surface.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/camera/frame_projector.h"
#include "core/controllers/stereo_seabed.h"
#include "core/terrain/height_grid_io.h"
#include "core/terrain/painting_surface.h"
#include "core/trajectory/seabed_terrain.h"
#include "core/util/error.h"
#include "core/util/progress.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

// The painted surface's cells: about this many ground pixels (finer makes the
// line-of-sight march slower and follows nothing the model knows), at most
// kMaxRefine per model cell and kMaxPaintedCells in all (4 bytes each).
constexpr double kPaintedCellGsd = 10;
constexpr int kMaxRefine = 4;
constexpr double kMaxPaintedCells = 64.0 * 1024 * 1024;

}  // namespace

std::string SeabedSurface::Summary() const {
  if (!grid) return "flat seabed (the plane at each frame's altitude)";
  char line[400];
  std::snprintf(line, sizeof line,
                "terrain %s: %dx%d cells of %.0f mm, painted on cells of %.0f mm; %.1f %% of the frames' footprint "
                "without a height, continued from the model there but %.1f %% painted on the frame's own plane; "
                "%+.2f m from the navigation's seabed (median)",
                source.c_str(), grid->cols(), grid->rows(), grid->cell_m * 1000,
                grid->cell_m * 1000 / std::max(1, painted_refine), hole_share * 100, painted_hole_share * 100,
                datum_offset_m);
  return line;
}

double HoleShare(const HeightGrid& grid, const CameraModel& camera, const std::vector<FrameSpec>& frames) {
  int samples = 0, holes = 0;
  for (const FrameSpec& f : frames) {
    const auto corners = Footprint(camera, f.pose);
    if (!corners) continue;
    std::vector<LocalXY> points(corners->begin(), corners->end());
    LocalXY centre{0, 0};
    for (const auto& c : *corners) centre = {centre.east + c.east / 4, centre.north + c.north / 4};
    points.push_back(centre);
    // Halfway between the centre and each corner too: most of what a frame paints.
    for (const auto& c : *corners) points.push_back({(c.east + centre.east) / 2, (c.north + centre.north) / 2});
    for (const LocalXY& p : points) {
      double h = 0;
      ++samples;
      holes += !grid.Sample(p, &h);
    }
  }
  return samples ? static_cast<double>(holes) / samples : 0;
}

void CheckAgainstNavigation(const CameraModel& camera, const std::vector<FrameSpec>& frames, const std::string& option,
                            SeabedSurface* surface) {
  const HeightGrid& grid = *surface->grid;
  surface->hole_share = HoleShare(grid, camera, frames);
  // What the frames are painted onto: holes near data continued, cells
  // refined to about kPaintedCellGsd ground pixels (painting_surface.h).
  std::vector<double> altitudes_m;
  for (const FrameSpec& f : frames) altitudes_m.push_back(f.pose.altitude_m);
  PaintingSurfaceOptions painting;
  if (!altitudes_m.empty() && camera.fx > 0) {
    const double gsd_m = Median(altitudes_m) / camera.fx;
    painting.refine = std::clamp(static_cast<int>(grid.cell_m / (kPaintedCellGsd * gsd_m)), 1, kMaxRefine);
    while (painting.refine > 1 &&
           static_cast<double>(grid.rows()) * grid.cols() * painting.refine * painting.refine > kMaxPaintedCells)
      --painting.refine;
  }
  PaintingSurfaceReport painted_report;
  auto painted = std::make_shared<HeightGrid>(PaintingSurface(grid, painting, &painted_report));
  surface->painted_hole_share = HoleShare(*painted, camera, frames);
  surface->painted_refine = painting.refine;
  surface->painted = std::move(painted);
  std::vector<double> offsets, altitudes;
  for (const FrameSpec& f : frames) {
    double up = 0;
    altitudes.push_back(f.pose.altitude_m);
    if (grid.Sample({f.pose.east_m, f.pose.north_m}, &up)) offsets.push_back(up + f.pose.depth_m + f.pose.altitude_m);
  }
  if (frames.empty()) return;
  const std::string& what = surface->path;
  if (offsets.empty())
    throw InputError(what, 0, option, "the height model has no height below any frame: not this survey's site?");
  surface->datum_offset_m = Median(offsets);
  const double limit = std::max(1.0, 0.5 * Median(altitudes));
  if (std::fabs(surface->datum_offset_m) > limit) {
    char detail[320];
    std::snprintf(detail, sizeof detail,
                  "the height model is %.2f m %s the seabed the navigation puts below the frames (-(depth_m + "
                  "altitude_m), median over %zu frames): it must be metres up on the same vertical datum (sea "
                  "surface 0 when the navigation has depth_m)",
                  std::fabs(surface->datum_offset_m), surface->datum_offset_m > 0 ? "above" : "below", offsets.size());
    throw InputError(what, 0, option, detail);
  }
}

SeabedSurface ReadSeabedSurface(const std::string& path, const LocalFrame& frame, const CameraModel& camera,
                                const std::vector<FrameSpec>& frames) {
  // The frames' flat footprints, and as far again as the highest altitude
  // around them (relief, and rays past the plane, reach beyond them).
  double e0 = 1e300, e1 = -1e300, n0 = 1e300, n1 = -1e300, reach = 1;
  for (const FrameSpec& f : frames) {
    reach = std::max(reach, f.pose.altitude_m);
    const auto corners = Footprint(camera, f.pose);
    if (!corners) continue;
    for (const LocalXY& c : *corners)
      e0 = std::min(e0, c.east), e1 = std::max(e1, c.east), n0 = std::min(n0, c.north), n1 = std::max(n1, c.north);
  }
  const cv::Rect2d extent =
      e0 <= e1 ? cv::Rect2d(e0 - reach, n0 - reach, e1 - e0 + 2 * reach, n1 - n0 + 2 * reach) : cv::Rect2d();
  SeabedSurface out;
  auto grid = std::make_shared<HeightGrid>(ReadHeightGridGeotiff(path, frame.origin(), extent));
  if (grid->empty()) throw InputError(path, 0, "--terrain-file", "holds no heights");
  out.grid = std::move(grid);
  out.source = "file " + path;
  out.path = path;
  return out;
}

SeabedSurface EstimateSeabedSurface(const LocalFrame& frame, const CameraModel& camera,
                                    const std::vector<FrameSpec>& frames, const TerrainSettings& settings, int threads,
                                    bool show_progress, int64_t max_image_pixels, const SeabedPoints* bundle_points) {
  TerrainOptions options;  // the frames' poses are in frame's local metres already
  if (!settings.points_file.empty()) options.extra_points = ReadStereoSeabedPoints(settings.points_file, frame);
  options.threads = threads;
  options.max_image_pixels = max_image_pixels;
  if (settings.max_relief_m != 0) options.tracks.max_relief_m = settings.max_relief_m;
  if (settings.cell_m != 0) options.fit.cell_m = settings.cell_m;
  if (settings.max_sigma_m != 0) options.fit.max_sigma_m = settings.max_sigma_m;
  options.Check();  // InputError naming --max-relief, --dem-cell or --dem-max-sigma
  SeabedSurface out;
  const bool reuse = bundle_points && !bundle_points->empty() && settings.from_bundle;
  if (reuse) {
    // The bundle estimated these points with the poses the frames are
    // painted with: fitting them keeps poses and terrain one estimate, and
    // reads no photo again.
    std::vector<VehiclePose> poses;
    poses.reserve(frames.size());
    for (const FrameSpec& f : frames) poses.push_back(f.pose);
    HeightGrid grid = FitSeabedTerrain(*bundle_points, poses, camera, options.fit, options.tracks.max_relief_m);
    if (!grid.empty()) {
      out.grid = std::make_shared<HeightGrid>(std::move(grid));
      out.source = "fitted to the bundle adjustment's " + std::to_string(bundle_points->size()) + " seabed points";
      return out;
    }
    // Too few of them for a model: the photos are matched again below.
  }
  TerrainReport report;
  ProgressBar bar("frames triangulated", static_cast<long>(frames.size()), show_progress);
  HeightGrid grid =
      EstimateSeabedTerrain(frames, camera, options, &report, [&](const std::string& stage, int done, int) {
        if (stage == "tracks") bar.Update(done);
      });
  bar.Finish();
  if (grid.empty())
    throw InputError("", 0, "--terrain",
                     "no seabed point could be triangulated from the photos (" +
                         std::to_string(report.frames_unreadable) + " of " + std::to_string(report.frames) +
                         " frames unreadable): too little texture or overlap; give a height model with --terrain-file");
  out.grid = std::make_shared<HeightGrid>(std::move(grid));
  out.source = "estimated from the photos";
  if (!options.extra_points.empty())
    out.source += " and " + std::to_string(options.extra_points.size()) + " points of " + settings.points_file;
  if (settings.from_bundle) out.source += " (the bundle's points fitted no model)";
  return out;
}

}  // namespace seamap
