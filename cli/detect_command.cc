// seamap detect: the recogniser on a finished map (spec detections-on-tiles).
#include <cstdio>
#include <optional>
#include <string>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/detect_setup.h"
#include "core/controllers/object_detection.h"

namespace seamap::cli {
namespace {

const char* kHelp =
    "usage: seamap detect MAP [options]\n"
    "\n"
    "Searches a map's tiles for objects with a YOLO model (ONNX, v5 or v8 layout),\n"
    "stores them in the mission (source \"recogniser\") and prints counts per class.\n"
    "\n"
    "  --model FILE      ONNX model (default: data/models/seabed_objects.onnx)\n"
    "  --classes FILE    class names, one per line (default: the model's metadata)\n"
    "  --zooms LIST      levels to search, e.g. 22,20,18 (default: base, base-2, ...\n"
    "                    until the model's largest class fits)\n"
    "  --min-score S     drop boxes scoring below S, 0.001..1 (default: the model's\n"
    "                    seamap.min_score metadata, else 0.4; its per-class\n"
    "                    seamap.class_min_scores, when it has them, unless S is given)\n"
    "  --layer NAME      raw | enhanced: the tiles searched (default raw)\n"
    "  --out FILE        also write the detections as GeoJSON\n"
    "  --threads N       windows searched at once, one network each (default 1)\n"
    "  --keep-cut-views  keep boxes cut by a window edge whose class is seen whole\n"
    "                    at a searched level (dropped by default: pieces of long objects)\n"
    "  --quiet           no progress bar\n";

}  // namespace

int RunDetect(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help", "quiet", "keep-cut-views"});
  if (args.Flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  ObjectDetectionOptions options;
  options.model_path = args.GetOr("model", DefaultModelPath());
  options.classes_path = args.GetOr("classes", "");
  if (const std::optional<std::string> zooms = args.Get("zooms")) options.zooms = ParseZooms(*zooms, "--zooms");
  options.min_score = MinScoreArg(args);
  const std::string layer = args.GetOr("layer", "raw");
  const std::optional<std::string> out = args.Get("out");
  options.quiet = args.Flag("quiet");
  options.keep_cut_views = args.Flag("keep-cut-views");
  options.threads = args.GetInt("threads", 1);
  args.RejectUnknown();
  options.Check();  // --threads before the arguments are counted; --layer (still the default) after
  if (args.positionals().size() != 1) {
    std::fputs(kHelp, stderr);
    return 2;
  }
  options.layer = layer;
  options.map_path = args.positionals()[0];
  const ObjectDetectionResult found = DetectObjects(options);
  if (out) WriteGeoJson(found.objects, *out, "--out");
  PrintDetectSummary(found.objects, found.stats, "");
  return 0;
}

}  // namespace seamap::cli
