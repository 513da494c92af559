// seamap trajectory-eval: a trajectory against ground truth (ATE, drift,
// cross-pass seams, body-velocity errors); see core/trajectory/trajectory_eval.h.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/nav/nav_reader.h"
#include "core/trajectory/trajectory_eval.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kUsage = R"(usage: seamap trajectory-eval ESTIMATE TRUTH [--origin LAT,LON] [--json FILE]
Compares a trajectory (trajectory.csv, nav.csv, any navigation file `seamap build --nav`
reads) with ground truth (e.g. nav_truth.csv from `seamap simulate`). Frames are paired
by image name, else by time (nearest, within a quarter frame interval, at most 0.05 s).
  --origin LAT,LON   origin of x_m/y_m positions (needed when a file has no lat/lon);
                     without it both files must have lat/lon
  --json FILE        also write the figures as JSON
Prints, with no alignment of the tracks (both are absolute):
  ATE                RMS horizontal error; RMSE north/east and maximum errors
  drift              maximum error / truth path length x 100 (the seed paper's measure)
  end-point error    at the last frame
  velocity           RMSE, mean, std of surge/sway/heave (u, v, w) errors, body frame of
                     the truth attitude, from central differences of positions and depth
  cross-pass pairs   frames on different survey lines (runs of truth heading within 20
                     degrees) whose true centres are < 1 m apart: error of their relative
                     position |(p_i - p_j) - (true_i - true_j)| in mm, median/p90/max
Exit 2 for unreadable input or no frames in common.
)";

// Both files in one local frame: --origin, else the estimate's (first record).
// Without --origin a local x_m/y_m file stops with the reader's "needs --origin".
std::pair<NavTable, NavTable> ReadBoth(const std::string& est_path, const std::string& truth_path,
                                       const std::optional<LatLon>& origin) {
  NavReadOptions options;
  options.origin = origin;
  NavTable estimate = ReadNavigation(est_path, options);
  NavTable truth = ReadNavigation(truth_path, options);
  if (!origin) {  // both geographic (else the reader threw): bring the truth into the estimate's frame
    options.origin = estimate.origin;
    truth = ReadNavigation(truth_path, options);
  }
  return {std::move(estimate), std::move(truth)};
}

void Report(const NavTable& table) {
  for (const auto& w : table.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (!table.rejected.empty())
    std::fprintf(stderr, "warning: %zu lines of %s skipped; first: %s\n", table.rejected.size(), table.source.c_str(),
                 table.rejected.front().Message().c_str());
}

std::string Fixed(double value, const char* format) {
  if (std::isnan(value)) return "n/a";
  char text[32];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

void Print(const TrajectoryErrors& e, const NavTable& estimate, const NavTable& truth) {
  std::printf("trajectory-eval: %s against %s\n", estimate.source.c_str(), truth.source.c_str());
  std::printf("frames            %d paired by %s (of %zu estimate, %zu truth records)\n", e.frames, e.paired_by.c_str(),
              estimate.records.size(), truth.records.size());
  std::printf("truth path        %.2f m, %d survey lines\n", e.path_length_m, e.lines);
  std::printf("ATE (RMS)         %.4f m  (no alignment)\n", e.ate_m);
  std::printf("RMSE north/east   %.4f / %.4f m\n", e.rmse_north_m, e.rmse_east_m);
  std::printf("max error         %.4f m  (north %.4f m, east %.4f m)\n", e.max_error_m, e.max_north_m, e.max_east_m);
  std::printf("drift             %s %% of distance (max error / path length)\n",
              Fixed(e.drift_percent, "%.3f").c_str());
  std::printf("end-point error   %.4f m\n", e.end_error_m);
  const char* axis[3] = {"u", "v", "w"};
  std::printf("velocity (m/s)    %d frames\n", e.velocity_frames);
  for (int k = 0; k < 3; ++k)
    std::printf("  %s  RMSE %s  mean %s  std %s\n", axis[k], Fixed(e.velocity[k].rmse, "%.4f").c_str(),
                Fixed(e.velocity[k].mean, "%+.4f").c_str(), Fixed(e.velocity[k].std, "%.4f").c_str());
  std::printf("cross-pass pairs  %d: median %s mm, p90 %s mm, max %s mm\n", e.cross_pairs,
              Fixed(e.cross_median_mm, "%.1f").c_str(), Fixed(e.cross_p90_mm, "%.1f").c_str(),
              Fixed(e.cross_max_mm, "%.1f").c_str());
}

// NaN (no pairs, no times) as null: JSON has no NaN.
nlohmann::json Number(double value) {
  return std::isnan(value) ? nlohmann::json() : nlohmann::json(value);
}

nlohmann::json ToJson(const TrajectoryErrors& e, const NavTable& estimate, const NavTable& truth) {
  nlohmann::json velocity = nlohmann::json::object();
  const char* axis[3] = {"u", "v", "w"};
  for (int k = 0; k < 3; ++k)
    velocity[axis[k]] = {{"rmse_mps", Number(e.velocity[k].rmse)},
                         {"mean_mps", Number(e.velocity[k].mean)},
                         {"std_mps", Number(e.velocity[k].std)}};
  return {{"estimate", estimate.source},
          {"truth", truth.source},
          {"frames", e.frames},
          {"paired_by", e.paired_by},
          {"path_length_m", e.path_length_m},
          {"lines", e.lines},
          {"ate_m", e.ate_m},
          {"rmse_north_m", e.rmse_north_m},
          {"rmse_east_m", e.rmse_east_m},
          {"max_error_m", e.max_error_m},
          {"max_north_m", e.max_north_m},
          {"max_east_m", e.max_east_m},
          {"drift_percent", Number(e.drift_percent)},
          {"end_error_m", e.end_error_m},
          {"velocity_frames", e.velocity_frames},
          {"velocity", velocity},
          {"cross_pairs", e.cross_pairs},
          {"cross_median_mm", Number(e.cross_median_mm)},
          {"cross_p90_mm", Number(e.cross_p90_mm)},
          {"cross_max_mm", Number(e.cross_max_mm)}};
}

}  // namespace

int RunTrajectoryEval(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  std::optional<LatLon> origin;
  if (auto text = args.Get("origin")) {
    const LatLonArg ll = ParseLatLon(*text, "--origin");
    origin = LatLon{ll.lat, ll.lon};
  }
  const std::optional<std::string> json_path = args.Get("json");
  args.RejectUnknown();
  if (args.positionals().size() != 2)
    throw InputError("", 0, "ESTIMATE TRUTH",
                     "expected two navigation files, got " + std::to_string(args.positionals().size()) +
                         "; see seamap trajectory-eval --help");

  const auto [estimate, truth] = ReadBoth(args.positionals()[0], args.positionals()[1], origin);
  Report(estimate);
  Report(truth);
  const TrajectoryErrors errors = EvaluateTrajectory(estimate, truth);
  Print(errors, estimate, truth);
  if (json_path) {
    std::ofstream out(*json_path, std::ios::trunc);
    if (out) out << ToJson(errors, estimate, truth).dump(2) << "\n";
    if (!out) throw InputError(*json_path, 0, "--json", "cannot write the JSON file");
  }
  return 0;
}

}  // namespace seamap::cli
