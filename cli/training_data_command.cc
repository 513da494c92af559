// seamap training-data: reviewed missions as YOLO training data (issue 32).
#include <cstdio>
#include <optional>
#include <string>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/detect_setup.h"
#include "core/detect/training_data.h"

namespace seamap::cli {
namespace {

const char* kHelp =
    "usage: seamap training-data MAP... --out DIR [options]\n"
    "\n"
    "Writes the recogniser's windows of reviewed missions with YOLO labels: confirmed\n"
    "detections and operator marks with a box are labels, rejected detections hard\n"
    "negatives (their window written, their box no label); unconfirmed ones are painted\n"
    "grey. DIR/images/*.png (the windows as composed), DIR/labels/*.txt, DIR/manifest.json.\n"
    "\n"
    "  --out DIR         the folder to write (must not exist unless --overwrite)\n"
    "  --overwrite       replace DIR's images/, labels/ and manifest.json\n"
    "  --model FILE      the model whose classes come first and whose class sizes choose\n"
    "                    the levels (default: data/models/seabed_objects.onnx)\n"
    "  --zooms LIST      levels, e.g. 25,23 (default: the recogniser's)\n"
    "  --empty K         windows touching no detection, K per labelled window (default 1)\n"
    "  --seed N          of the empty windows' sample (default 1)\n"
    "  --quiet           no progress bar\n";

}  // namespace

int RunTrainingData(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help", "quiet", "overwrite"});
  if (args.Flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  TrainingDataOptions options;
  options.out_dir = args.GetOr("out", "");
  options.overwrite = args.Flag("overwrite");
  options.model_path = args.GetOr("model", DefaultModelPath());
  if (const std::optional<std::string> zooms = args.Get("zooms")) options.zooms = ParseZooms(*zooms, "--zooms");
  options.empty_per_labelled = args.GetDouble("empty", 1);
  options.seed = SeedArg(args);
  options.quiet = args.Flag("quiet");
  args.RejectUnknown();
  options.maps = args.positionals();
  options.Check();
  const TrainingDataSummary s = WriteTrainingData(options);
  std::printf("training data: %d windows (%d empty), %d labels, %d negatives -> %s\n", s.windows, s.empty, s.labels,
              s.negatives, options.out_dir.c_str());
  for (const auto& [name, count] : s.per_class) std::printf("  %-12s %d\n", name.c_str(), count);
  if (s.ignored > 0 || s.skipped > 0)
    std::printf("  not labels: %d detections (unconfirmed, stereo, point marks); %d windows left out\n", s.ignored,
                s.skipped);
  return 0;
}

}  // namespace seamap::cli
