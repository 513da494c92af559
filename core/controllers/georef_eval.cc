#include "core/controllers/georef_eval.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include <Eigen/Geometry>

#include "core/geo/local_frame.h"
#include "core/geo/utm.h"
#include "core/georef/point_cloud_ply.h"
#include "core/nav/csv_numbers.h"
#include "core/nav/nav_values.h"
#include "core/util/error.h"
#include "core/util/json_file.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

using Row = CsvNumbers;

Eigen::Matrix3d Rotation(const nlohmann::json& values) {
  Eigen::Matrix3d r;
  for (int k = 0; k < 9; ++k) r(k / 3, k % 3) = values.at(k).get<double>();
  return r;
}

// Refuses a value no survey could hold (1e308 would make every RMSE inf):
// InputError naming the file, line and column.
void RequireWithin(const std::string& path, const std::vector<Row>& rows, const std::string& column, double lowest,
                   double highest) {
  for (size_t i = 0; i < rows.size(); ++i) {
    const double v = rows[i].at(column);
    if (!(v >= lowest && v <= highest))
      throw InputError(path, 0, column,
                       "row " + std::to_string(i + 1) + ": " + FormatNumber(v) + " is out of range, expected " +
                           FormatNumber(lowest) + " to " + FormatNumber(highest));
  }
}

double Rms(const std::vector<double>& v) {
  double sq = 0;
  for (double x : v) sq += x * x;
  return v.empty() ? 0 : std::sqrt(sq / v.size());
}

}  // namespace

GeorefEvaluation EvaluateGeoref(const GeorefEvalOptions& o) {
  const nlohmann::json truth_json = ReadJsonFile(o.truth_dir + "/truth.json", "ground truth");
  const LatLon origin{truth_json.at("origin").at("lat").get<double>(), truth_json.at("origin").at("lon").get<double>()};
  const LocalFrame frame(origin);
  const auto nav = ReadCsvNumbers(o.nav_path, {"time_s", "lat", "lon", "depth_m", "heading_deg", "good"});
  auto truth = ReadCsvNumbers(o.truth_dir + "/truth.csv", {"time_s", "x_m", "y_m", "depth_m", "heading_deg"});
  if (nav.empty()) throw InputError(o.nav_path, 0, "", "no keyframes: the file has a header and no rows");
  if (truth.empty()) throw InputError(o.truth_dir + "/truth.csv", 0, "", "no rows after the header");
  // Bounds far beyond any survey, tight enough that the errors stay finite.
  constexpr double kMaxMetres = 1e7, kMaxDepthM = 12000, kMaxHeadingDeg = 3600;
  RequireWithin(o.nav_path, nav, "lat", -90, 90);
  RequireWithin(o.nav_path, nav, "lon", -180, 180);
  RequireWithin(o.nav_path, nav, "depth_m", -kMaxDepthM, kMaxDepthM);
  RequireWithin(o.nav_path, nav, "heading_deg", -kMaxHeadingDeg, kMaxHeadingDeg);
  for (const char* column : {"x_m", "y_m"})
    RequireWithin(o.truth_dir + "/truth.csv", truth, column, -kMaxMetres, kMaxMetres);
  RequireWithin(o.truth_dir + "/truth.csv", truth, "depth_m", -kMaxDepthM, kMaxDepthM);
  RequireWithin(o.truth_dir + "/truth.csv", truth, "heading_deg", -kMaxHeadingDeg, kMaxHeadingDeg);
  std::sort(truth.begin(), truth.end(), [](const Row& a, const Row& b) { return a.at("time_s") < b.at("time_s"); });

  std::vector<double> horizontal, good, vertical, heading;
  for (const Row& n : nav) {
    const double t = n.at("time_s");
    auto it = std::lower_bound(truth.begin(), truth.end(), t - 1e-3,
                               [](const Row& r, double time) { return r.at("time_s") < time; });
    if (it == truth.end() || std::fabs(it->at("time_s") - t) > 1e-3)
      throw InputError(o.nav_path, 0, "time_s", "keyframe at " + FormatNumber(t) + " s is not in the truth");
    const LocalXY xy = frame.FromLatLon({n.at("lat"), n.at("lon")});
    const double e = std::hypot(xy.east - it->at("x_m"), xy.north - it->at("y_m"));
    horizontal.push_back(e);
    if (n.at("good") != 0) good.push_back(e);
    vertical.push_back(n.at("depth_m") - it->at("depth_m"));
    heading.push_back(std::remainder(n.at("heading_deg") - it->at("heading_deg"), 360.0));
  }
  nlohmann::json result = {{"keyframes", horizontal.size()},
                           {"good_keyframes", good.size()},
                           {"rmse_m", Rms(horizontal)},
                           {"good_rmse_m", Rms(good)},
                           {"p95_m", Percentile(horizontal, 0.95)},
                           {"max_m", Percentile(horizontal, 1.0)},
                           {"vertical_rmse_m", Rms(vertical)},
                           {"heading_rms_deg", Rms(heading)}};
  char line[512];
  std::snprintf(line, sizeof line,
                "keyframes %zu (%zu good): horizontal RMSE %.3f m, good %.3f m, p95 %.3f m, max %.3f m; vertical "
                "RMSE %.3f m; heading %.2f deg RMS",
                horizontal.size(), good.size(), Rms(horizontal), Rms(good), Percentile(horizontal, 0.95),
                Percentile(horizontal, 1.0), Rms(vertical), Rms(heading));
  std::string text = line;

  if (!o.report_path.empty()) {
    const nlohmann::json report = ReadJsonFile(o.report_path, "georeferencing report");
    const auto& fitted = report.at("submaps");
    const auto& true_maps = truth_json.at("submaps");
    nlohmann::json per = nlohmann::json::array();
    for (size_t k = 0; k < std::min(fitted.size(), true_maps.size()); ++k) {
      if (!fitted[k].contains("scale")) continue;
      const double scale_error =
          100 * (fitted[k].at("scale").get<double>() / true_maps[k].at("scale").get<double>() - 1);
      const Eigen::AngleAxisd diff(Rotation(fitted[k].at("rotation")) *
                                   Rotation(true_maps[k].at("rotation")).transpose());
      const double angle = diff.angle() * 180 / M_PI;
      per.push_back({{"scale_error_pct", scale_error}, {"rotation_error_deg", angle}});
      std::snprintf(line, sizeof line, "; sub-map %zu: scale error %.3f %%, rotation error %.3f deg", k + 1,
                    scale_error, angle);
      text += line;
    }
    result["submaps"] = per;
  }
  if (!o.points.empty()) {
    const PointCloud fitted = ReadPly(o.points), truth_cloud = ReadPly(o.truth_dir + "/cloud_truth.ply");
    if (fitted.size() != truth_cloud.size())
      throw InputError(
          o.points, 0, "vertex",
          "has " + std::to_string(fitted.size()) + " points, the truth " + std::to_string(truth_cloud.size()));
    // The cloud is in UTM (zone in a comment) or local metres about an origin.
    std::optional<UtmZoneId> zone;
    std::optional<LatLon> cloud_origin;
    for (const auto& c : fitted.comments) {
      auto at = c.find("UTM zone ");
      if (at != std::string::npos) {
        std::istringstream in(c.substr(at + 9));
        std::string name;
        in >> name;
        std::string why;
        if (auto z = ParseUtmZone(name, &why)) zone = UtmZoneId{z->zone, z->north.value_or(true)};
      }
      at = c.find("about the origin ");
      if (at != std::string::npos) {
        double lat = 0, lon = 0;
        if (std::sscanf(c.c_str() + at + 17, "%lf,%lf", &lat, &lon) == 2) cloud_origin = LatLon{lat, lon};
      }
    }
    if (!zone && !cloud_origin)
      throw InputError(o.points, 0, "comment", "no 'UTM zone' or 'about the origin' comment: cannot tell its frame");
    std::optional<UtmProjection> utm;
    if (zone) utm.emplace(*zone);
    std::optional<LocalFrame> local;
    if (cloud_origin) local.emplace(*cloud_origin);
    std::vector<double> h, v;
    for (size_t i = 0; i < fitted.size(); ++i) {
      const Eigen::Vector3d p = fitted.Point(i), q = truth_cloud.Point(i);
      const LatLon ll = utm ? utm->Inverse({p.x(), p.y()}) : local->ToLatLon({p.x(), p.y()});
      const LocalXY xy = frame.FromLatLon(ll);
      h.push_back(std::hypot(xy.east - q.x(), xy.north - q.y()));
      v.push_back(p.z() - q.z());
    }
    result["cloud"] = {{"points", h.size()}, {"rmse_m", Rms(h)}, {"vertical_rmse_m", Rms(v)}};
    std::snprintf(line, sizeof line, "; cloud %zu points: horizontal RMSE %.3f m, vertical %.3f m", h.size(), Rms(h),
                  Rms(v));
    text += line;
  }
  return {result, text};
}

}  // namespace seamap
