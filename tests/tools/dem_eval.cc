// dem_eval: the height model from a simulated survey's photos against its
// truth (scripts/bench_dem.sh), until `build --terrain` stores one.
//
//   dem_eval SURVEY [--nav nav_truth.csv] [--threads N] [--cell M] [--dump PREFIX] [--quiet]
//   dem_eval SURVEY --dem DEM.tif     (a model a build stored: seamap export MAP DEM.tif --dem)
//
// SURVEY is a `seamap simulate --relief M` folder. The frames are placed with
// --nav (default nav_truth.csv: exact navigation), the height model
// estimated from the photos (EstimateSeabedTerrain) and compared with
// truth/terrain.tif over the surveyed swath, after removing the mean offset.
// Prints one line: rms_mm p90_mm coverage within1 within2 cell_m points
// cpu_s peak_mb.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/camera/camera_model.h"
#include "core/nav/frame_list.h"
#include "core/nav/nav_reader.h"
#include "core/terrain/height_grid_io.h"
#include "core/trajectory/seabed_terrain.h"
#include "core/util/process_stats.h"
#include "core/util/progress.h"
#include "core/util/statistics.h"

namespace {

int Run(int argc, char** argv) {
  using namespace seamap;
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: dem_eval SURVEY [--nav nav_truth.csv] [--threads N] [--cell M] [--dump PREFIX] [--quiet]\n"
                 "       dem_eval SURVEY --dem DEM.tif\n");
    return 2;
  }
  const std::string survey = argv[1];
  std::string nav_name = "nav_truth.csv";
  TerrainOptions options;
  bool quiet = false;
  std::string dem;   // a stored model to compare instead of estimating one
  std::string dump;  // prefix: DUMP_grid.csv and DUMP_points.csv with the truth beside
  for (int k = 2; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--quiet") {
      quiet = true;
    } else if (k + 1 < argc && a == "--nav") {
      nav_name = argv[++k];
    } else if (k + 1 < argc && a == "--threads") {
      options.threads = std::atoi(argv[++k]);
    } else if (k + 1 < argc && a == "--dem") {
      dem = argv[++k];
    } else if (k + 1 < argc && a == "--dump") {
      dump = argv[++k];
    } else if (k + 1 < argc && a == "--cell") {
      options.fit.cell_m = std::atof(argv[++k]);
    } else {
      std::fprintf(stderr, "dem_eval: unknown argument %s\n", a.c_str());
      return 2;
    }
  }
  const CameraModel camera = LoadCamera(survey + "/camera.json");
  NavReadOptions nav_options;
  const nlohmann::json description = nlohmann::json::parse(std::ifstream(survey + "/survey.json"));
  const LatLon origin{description.at("origin").at(0).get<double>(), description.at("origin").at(1).get<double>()};
  nav_options.origin = origin;
  const NavTable nav = ReadNavigation(survey + "/" + nav_name, nav_options);
  const FrameList frames = MatchFrames(nav, survey + "/photo", std::nullopt);
  if (!dem.empty()) {  // the model's cells against the truth, the mean offset removed
    const HeightGrid model = ReadHeightGridGeotiff(dem, origin);
    const HeightGrid truth = ReadHeightGridGeotiff(survey + "/truth/terrain.tif", origin);
    std::vector<double> error;
    for (int r = 0; r < model.rows(); ++r)
      for (int c = 0; c < model.cols(); ++c) {
        double t = 0;
        if (std::isfinite(model.height_m(r, c)) && truth.Sample(model.CellCentre(r, c), &t))
          error.push_back(model.height_m(r, c) - t);
      }
    double mean = 0, sum = 0;
    for (double e : error) mean += e / error.size();
    std::vector<double> absolute;
    for (double e : error) {
      sum += (e - mean) * (e - mean);
      absolute.push_back(std::fabs(e - mean));
    }
    std::printf("rms_mm %.2f p90_mm %.2f offset_mm %.1f cells %zu cell_m %.3f\n",
                1000 * std::sqrt(sum / std::max<size_t>(1, error.size())), 1000 * Percentile(absolute, 0.9),
                1000 * mean, error.size(), model.cell_m);
    return error.empty() ? 1 : 0;
  }

  ProgressBar bar("frames", static_cast<long>(frames.frames.size()), !quiet);
  TerrainReport report;
  SeabedTracks tracks;
  const HeightGrid grid = EstimateSeabedTerrain(
      frames.frames, camera, options, &report,
      [&](const std::string& stage, int done, int) {
        if (stage == "tracks") bar.Update(done);
      },
      dump.empty() ? nullptr : &tracks);
  bar.Finish();
  if (grid.empty()) {
    std::fprintf(stderr, "dem_eval: no height model (%d frames unreadable)\n", report.frames_unreadable);
    return 1;
  }
  const HeightGrid truth = ReadHeightGridGeotiff(survey + "/truth/terrain.tif", origin);
  if (!dump.empty()) {
    std::ofstream g(dump + "_grid.csv"), p(dump + "_points.csv");
    g << "east,north,up,sigma,truth\n";
    for (int r = 0; r < grid.rows(); ++r)
      for (int c = 0; c < grid.cols(); ++c) {
        double t = NAN;
        truth.Sample(grid.CellCentre(r, c), &t);
        g << grid.CellCentre(r, c).east << "," << grid.CellCentre(r, c).north << "," << grid.height_m(r, c) << ","
          << grid.sigma_m(r, c) << "," << t << "\n";
      }
    p << "east,north,up,sigma,views,rms_px,angle_deg,truth\n";
    for (const SeabedTrack& k : tracks.tracks) {
      double t = NAN;
      truth.Sample({k.east_north_up_m.x(), k.east_north_up_m.y()}, &t);
      p << k.east_north_up_m.x() << "," << k.east_north_up_m.y() << "," << k.east_north_up_m.z() << "," << k.sigma_up_m
        << "," << k.observations.size() << "," << k.reprojection_rms_px << "," << k.ray_angle_deg << "," << t << "\n";
    }
  }
  std::vector<double> error, sigma;
  for (int r = 0; r < grid.rows(); ++r)
    for (int c = 0; c < grid.cols(); ++c) {
      double t = 0;
      if (!std::isfinite(grid.height_m(r, c)) || !truth.Sample(grid.CellCentre(r, c), &t)) continue;
      error.push_back(grid.height_m(r, c) - t);
      sigma.push_back(grid.sigma_m(r, c));
    }
  double mean = 0;
  for (double e : error) mean += e / error.size();
  double sum = 0, within1 = 0, within2 = 0;
  std::vector<double> absolute;
  for (size_t k = 0; k < error.size(); ++k) {
    const double e = std::fabs(error[k] - mean);
    sum += e * e;
    absolute.push_back(e);
    within1 += e <= sigma[k];
    within2 += e <= 2 * sigma[k];
  }
  const double n = std::max<double>(1, error.size());
  std::printf(
      "rms_mm %.2f p90_mm %.2f offset_mm %.1f coverage %.3f within1 %.3f within2 %.3f cell_m %.3f points %ld "
      "frames %d cpu_s %.1f peak_mb %.0f\n",
      1000 * std::sqrt(sum / n), 1000 * Percentile(absolute, 0.9), 1000 * mean,
      static_cast<double>(error.size()) / std::max<long>(1, report.fit.cells_swath), within1 / n, within2 / n,
      report.fit.cell_m, report.tracks.points, report.frames, ProcessCpuSeconds(), PeakRssBytes() / 1e6);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dem_eval: %s\n", e.what());
    return 1;
  }
}
