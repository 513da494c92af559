// seamap map-eval: how far a built map's texture is from a simulated
// survey's truth (seamap simulate), in base pixels and millimetres.
#include <cstdio>
#include <fstream>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/controllers/map_eval.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kUsage = R"(usage: seamap map-eval MAP SURVEY_DIR [--block PX] [--json FILE]
Compares the map's base-zoom tiles with the simulated survey's truth texture (SURVEY_DIR/truth/,
seamap simulate) resampled into the same tiles: in every fully painted block of PX pixels
(default 64), the shift between them by phase correlation. Prints the median, 90th percentile and
largest shift in base pixels and millimetres, and the share of painted blocks that could be
measured (featureless ones cannot); --json writes the same figures.
)";

}  // namespace

int RunMapEval(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  MapEvalOptions options;
  options.block_px = args.GetInt("block", options.block_px);
  const std::string json_path = args.GetOr("json", "");
  args.RejectUnknown();
  if (args.positionals().size() != 2)
    throw InputError("", 0, "MAP SURVEY_DIR", "expected the map and the survey folder (see seamap map-eval --help)");
  options.map = args.positionals()[0];
  options.survey_dir = args.positionals()[1];
  const MapEvaluation evaluation = EvaluateMap(options);
  std::printf("%s\n", evaluation.text.c_str());
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << evaluation.figures.dump(2) << "\n";
    if (!out) throw InputError(json_path, 0, "--json", "cannot write the file");
  }
  return 0;
}

}  // namespace seamap::cli
