// seamap georef-eval: how far georef's keyframes (and cloud) are from a
// simulated survey's truth (seamap simulate-buoy).
#include <cstdio>
#include <fstream>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/controllers/georef_eval.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kUsage = R"(usage: seamap georef-eval --nav nav.csv --truth DIR [--report report.json]
                         [--points cloud_georef.ply] [--json FILE]
Compares georef's nav.csv with DIR/truth.csv (seamap simulate-buoy): horizontal error of every
keyframe (RMSE, good keyframes' RMSE, 95th percentile, maximum), vertical RMSE, heading error;
with --report, the scale and rotation errors of each sub-map against DIR/truth.json; with
--points, the georeferenced cloud against DIR/cloud_truth.ply (same point order).
)";

}  // namespace

int RunGeorefEval(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  GeorefEvalOptions options;
  options.nav_path = args.Require("nav"), options.truth_dir = args.Require("truth");
  options.report_path = args.GetOr("report", ""), options.points = args.GetOr("points", "");
  const std::string json_path = args.GetOr("json", "");
  args.RejectUnknown();
  const GeorefEvaluation evaluation = EvaluateGeoref(options);
  std::printf("%s\n", evaluation.text.c_str());
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << evaluation.figures.dump(2) << "\n";
    if (!out) throw InputError(json_path, 0, "--json", "cannot write the file");
  }
  return 0;
}

}  // namespace seamap::cli
