#include "core/georef/georef_report.h"

#include <cmath>

namespace seamap {
namespace {

nlohmann::json Vector(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

nlohmann::json SubmapReport(const SubmapGeoref& s) {
  nlohmann::json rotation = nlohmann::json::array();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rotation.push_back(s.transform.rotation(r, c));
  nlohmann::json triangle = nlohmann::json::array();
  for (int index : s.triangle)
    if (index >= 0) triangle.push_back({{"line", s.keyframes[index].line}, {"time_s", s.keyframes[index].time_s}});
  nlohmann::json resets = nlohmann::json::array();
  for (const auto& r : s.resets) resets.push_back({{"line", r.line}, {"why", r.why}});
  nlohmann::json j = {
      {"file", s.source},
      {"method", s.method},
      {"degenerate", s.degenerate},
      {"reason", s.reason},
      {"keyframes", s.keyframes.size()},
      {"good_keyframes", s.good},
      {"rejected", s.rejected},
      {"outliers", s.outliers},
      {"rounds", s.rounds},
      {"gps_sigma_m", s.gps_sigma_m},
      {"gps_sigma_source", s.gps_sigma_source},
      {"fix_rate_hz", s.fix_rate_hz},
      {"reach_m", s.reach_m},
      {"taut_time_s", s.taut_time_s},
      {"suspected_resets", resets},
      {"warnings", s.warnings},
  };
  if (!s.fitted) return j;
  j.update({{"scale", s.transform.scale},
            {"rotation", rotation},
            {"translation", Vector(s.transform.translation)},
            {"rmse_m", s.rmse_m},
            {"good_duration_s", s.good_duration_s},
            {"n_eff", s.n_eff},
            {"predicted_rmse_m", s.predicted_rmse_m},
            {"along_track_bias_m", s.along_track_bias_m},
            {"eigen_ratio", s.eigen_ratio},
            {"forward_axis", s.forward_axis},
            {"standard_errors",
             {{"rotation_deg_about_east_north_up", Vector(s.uncertainty.rotation_sigma_deg)},
              {"scale_relative", s.uncertainty.scale_sigma},
              {"position_m_at_centroid", Vector(s.uncertainty.position_sigma_m)}}}});
  j["gps_bound_rmse_m"] = s.gps_bound_rmse_m;
  if (s.method == "tether")
    j["tether_model"] = {{"reach_factor", s.reach_factor},
                         {"reach_factor_sigma", s.reach_factor_sigma},
                         {"reach_estimated", s.reach_estimated},
                         {"wake_estimated", s.wake_estimated},
                         {"current_mps", {s.current_mps.x(), s.current_mps.y()}},
                         {"current_sigma_mps", {s.current_sigma_mps.x(), s.current_sigma_mps.y()}},
                         {"current_estimated", s.current_estimated},
                         {"lag_s", s.lag_s},
                         {"lag_sigma_s", s.lag_sigma_s},
                         {"lag_estimated", s.lag_estimated},
                         {"model_bound_rmse_m", s.model_bound_rmse_m},
                         {"along_track_offset_m", s.along_track_offset_m},
                         {"along_track_offset_sigma_m", s.along_track_offset_sigma_m},
                         {"reach_lag_correlation", s.reach_lag_correlation},
                         {"reach_lag_separable", s.reach_lag_separable},
                         {"unseen_offset_rmse_m", s.unseen_offset_rmse_m},
                         {"selection_spread_rmse_m", s.selection_spread_rmse_m},
                         {"wake_share", s.wake_share},
                         {"wake_share_sigma", s.wake_share_sigma},
                         {"variance_factor", s.variance_factor},
                         {"correlation_factor", s.correlation_factor},
                         {"taut_model_sigma_m", s.taut_model_sigma_m},
                         {"slack_model_sigma_m", s.slack_model_sigma_m},
                         {"fixes_used", s.fixes_used},
                         {"taut_fixes", s.taut_fixes}};
  if (s.method == "triangle") j["triangle"] = {{"keyframes", triangle}, {"area_m2", s.triangle_area_m2}};
  return j;
}

nlohmann::json GeorefReport(const std::vector<SubmapGeoref>& submaps, const GeorefReportContext& c) {
  nlohmann::json per = nlohmann::json::array();
  int keyframes = 0, good = 0;
  double sq = 0, predicted_sq = 0, bound_sq = 0, n_eff = 0;
  std::map<std::string, int> rejected;
  bool degenerate = false;
  std::string reason;
  for (const auto& s : submaps) {
    per.push_back(SubmapReport(s));
    keyframes += static_cast<int>(s.keyframes.size());
    good += s.good;
    sq += s.rmse_m * s.rmse_m * s.good;
    predicted_sq += s.predicted_rmse_m * s.predicted_rmse_m * s.keyframes.size();
    bound_sq += s.gps_bound_rmse_m * s.gps_bound_rmse_m * s.keyframes.size();
    n_eff += s.n_eff;
    for (const auto& [r, n] : s.rejected) rejected[r] += n;
    if (s.degenerate && !degenerate) {
      degenerate = true;
      reason = s.source + ": " + s.reason;
    }
  }
  nlohmann::json j = SubmapReport(submaps.front());
  j.erase("file");
  j.update({{"degenerate", degenerate},
            {"reason", reason},
            {"keyframes", keyframes},
            {"good_keyframes", good},
            {"rejected", rejected},
            {"n_eff", n_eff},
            {"frame",
             {{"origin", {{"lat", c.origin.lat}, {"lon", c.origin.lon}}},
              {"axes", "metres east, north, up (= -depth); transverse Mercator on WGS84 centred on the origin"},
              {"transform",
               "position = scale * rotation * slam + translation (rotation row-major, SLAM axes to "
               "east, north, up); the first sub-map's"}}},
            {"utm_zone", c.utm_zone.Name()},
            {"epsg", c.utm_zone.Epsg()},
            {"buoy", {{"file", c.buoy_file}, {"fixes", c.buoy_fixes}, {"rows_rejected", c.buoy_rows_rejected}}},
            {"submaps", per},
            {"warnings", c.warnings}});
  if (good > 0) j["rmse_m"] = std::sqrt(sq / good);
  if (keyframes > 0 && j.contains("predicted_rmse_m")) {
    j["predicted_rmse_m"] = std::sqrt(predicted_sq / keyframes);
    j["gps_bound_rmse_m"] = std::sqrt(bound_sq / keyframes);
  }
  return j;
}

}  // namespace seamap
