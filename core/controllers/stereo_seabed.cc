#include "core/controllers/stereo_seabed.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include <opencv2/core.hpp>

#include "core/nav/csv_table.h"
#include "core/nav/nav_reader.h"
#include "core/nav/nav_series.h"
#include "core/nav/nav_values.h"
#include "core/stereo/pair_times.h"
#include "core/stereo/stereo_calibration.h"
#include "core/stereo/stereo_enhancement.h"
#include "core/stereo/stereo_pairs.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap {

void StereoPointsOptions::Check() const {
  if (nav_path.empty()) throw InputError("", 0, "--nav", "the pairs are placed on the vehicle's navigation: give it");
  sift.Check();
  points.Check();
  feature_enhance.Check();
}

StereoPointsReport WriteStereoSeabedPoints(const StereoPointsOptions& o) {
  o.Check();
  const StereoCalibration calibration = LoadStereoCalibration(o.calib_path);
  const std::vector<PairFiles> files = ListStereoPairs(o.pairs_dir);
  const std::optional<PairTimes> table =
      o.pair_times_path ? std::optional<PairTimes>(PairTimes::Read(*o.pair_times_path)) : std::nullopt;
  NavReadOptions nav_options;
  nav_options.origin = o.origin;
  const NavTable nav = ReadNavigation(o.nav_path, nav_options);
  if (!nav.has_times) throw InputError(o.nav_path, 0, "time_s", "the navigation has no times to place the pairs at");
  const NavSeries series(nav.records);
  const LocalFrame frame(nav.origin);

  // Every pair's time first: a pair without one is bad input, found before the slow part.
  StereoPointsReport report;
  report.pairs = static_cast<int>(files.size());
  std::vector<std::optional<VehiclePose>> poses;
  for (const PairFiles& f : files) {
    const std::optional<double> t = table ? table->Find(f.name, f.left, f.right) : PairTimeFromName(f.name);
    if (!t)
      throw InputError(table ? *o.pair_times_path : f.left, 0, table ? "image" : "--pair-times",
                       "no time for pair '" + Shorten(f.name, 100) +
                           (table ? "'" : "' in its name: give --pair-times FILE (image,time_s)"));
    poses.push_back(series.PoseAt(*t));
    if (!poses.back())
      report.skipped.push_back(
          f.name + ": " + cv::format("at %.3f s, outside the navigation's times (%s)", *t, series.SpanText().c_str()));
  }

  SiftOptions sift = o.sift;
  if (o.feature_enhance.spec != "off") {  // probed on the first pairs placed
    std::vector<LoadedPair> probe;
    for (size_t i = 0; i < files.size() && static_cast<int>(probe.size()) * 2 < o.feature_enhance.probe_frames; ++i)
      if (poses[i]) probe.push_back(LoadStereoPair(files[i], calibration.image_size, o.calib_path));
    const EnhancementChoice choice = ChooseStereoEnhancement(o.feature_enhance, probe, calibration, sift, o.match);
    sift.enhance = choice.chain;
    report.chain = choice.chain.Names();
    for (const EnhancementTrial& t : choice.trials)
      std::fprintf(stderr, "  %-40s %7.1f stereo inliers/pair\n", t.chain.c_str(), t.inliers);
  }

  std::ofstream out(o.out);
  if (!out) throw InputError(o.out, 0, "--out", "cannot write the points");
  out << "pair,lat,lon,up_m,sigma_up_m\n";
  ProgressBar progress("pairs", static_cast<long>(files.size()), !o.quiet);
  for (size_t i = 0; i < files.size(); ++i) {
    progress.Update(static_cast<long>(i + 1));
    if (!poses[i]) continue;
    const LoadedPair pair = LoadStereoPair(files[i], calibration.image_size, o.calib_path);
    StereoFrame stereo;
    try {
      stereo = MakeStereoFrame(pair.name, pair.left, pair.right, calibration, sift, o.match);
    } catch (const InputError& e) {  // not a pair for this calibration: reported, the others kept
      report.skipped.push_back(files[i].name + ": " + e.what());
      continue;
    }
    ++report.used;
    for (const SeabedPoint& p : StereoSeabedPoints(stereo, o.mount, *poses[i], o.points)) {
      const LatLon at = frame.ToLatLon({p.east_north_up_m.x(), p.east_north_up_m.y()});
      out << files[i].name << ','
          << cv::format("%.9f,%.9f,%.4f,%.5f", at.lat, at.lon, p.east_north_up_m.z(), p.sigma_up_m) << '\n';
      ++report.points;
    }
  }
  progress.Finish();
  out.close();
  if (!out) throw InputError(o.out, 0, "--out", "could not write the points (disk full?)");
  return report;
}

SeabedPoints ReadStereoSeabedPoints(const std::string& path, const LocalFrame& frame, long max_points) {
  const CsvTable table = ParseCsv(ReadTextLines(path), path);
  const auto column = [&](const std::string& name) {
    for (size_t k = 0; k < table.header.size(); ++k)
      if (Trim(table.header[k]) == name) return static_cast<int>(k);
    throw InputError(path, table.header_line, name,
                     "missing column (expected pair,lat,lon,up_m,sigma_up_m as seamap stereo-points writes)");
  };
  const int lat = column("lat"), lon = column("lon"), up = column("up_m"), sigma = column("sigma_up_m");
  if (static_cast<long>(table.rows.size()) > max_points)
    throw InputError(path, 0, "--terrain-points",
                     "holds " + std::to_string(table.rows.size()) + " points, at most " + std::to_string(max_points));
  SeabedPoints points;
  points.reserve(table.rows.size());
  for (const CsvRow& row : table.rows) {
    if (!row.problem.empty()) throw InputError(path, row.line, "", row.problem);
    const auto number = [&](int k, const char* name) {
      std::string why = "missing";
      const std::optional<double> v =
          k < static_cast<int>(row.fields.size()) ? ParseNumber(row.fields[k], &why) : std::nullopt;
      if (!v) throw InputError(path, row.line, name, why);
      return *v;
    };
    const double la = number(lat, "lat"), lo = number(lon, "lon");
    if (std::abs(la) > 90 || std::abs(lo) > 180)
      throw InputError(path, row.line, "lat", cv::format("expected a latitude and longitude, got %g %g", la, lo));
    SeabedPoint p;
    const LocalXY xy = frame.FromLatLon({la, lo});
    p.east_north_up_m = {xy.east, xy.north, number(up, "up_m")};
    p.sigma_up_m = number(sigma, "sigma_up_m");
    if (!(p.sigma_up_m > 0) || std::abs(p.east_north_up_m.z()) > 12000)
      throw InputError(path, row.line, "sigma_up_m", "expected a sigma > 0 and a height within 12 km of the surface");
    p.views = 2;
    points.push_back(p);
  }
  return points;
}

}  // namespace seamap
