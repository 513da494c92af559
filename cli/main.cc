// seamap: one executable, one subcommand per job.
#include <malloc.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <string>

#include "cli/commands.h"
#include "core/util/error.h"

namespace {

const char* kUsage =
    "usage: seamap <command> [options]\n"
    "\n"
    "commands:\n"
    "  simulate        render a test survey with exact ground truth\n"
    "  build           build a georeferenced tile map from photos and navigation\n"
    "  info            describe a built map (MBTiles file or tile folder)\n"
    "  enhance         apply the image enhancement chain to one image\n"
    "  enhance-report  measure what enhancement chains do to features and matches\n"
    "  serve           serve a built map: tiles, REST API, live events, operator console\n"
    "  replay          build a map while serving it, frames at their recorded pace (or --watch a folder)\n"
    "  export          copy a map between MBTiles and a tile folder, or write it as PMTiles or a GeoTIFF\n"
    "  trajectory      estimate a survey's trajectory from its photos (refine, vo, ekf)\n"
    "  trajectory-eval compare a trajectory with ground truth: ATE, drift, cross-pass seams\n"
    "  simulate-stereo render a stereo scene of a subsea object with exact truth\n"
    "  stereo-model    build an object model from stereo overview pairs\n"
    "  stereo-locate   recognise the object in stereo pairs: the camera's pose in its frame\n"
    "  stereo-points   stereo pairs as seabed points for the height model (build --terrain-points)\n"
    "  georef          georeference SLAM keyframes and point clouds from a towed GPS buoy\n"
    "  simulate-buoy   simulate a buoy-GPS survey with exact truth (for georef)\n"
    "  georef-eval     compare georef's output with a simulated survey's truth\n"
    "  map-eval        compare a map's texture with a simulated survey's truth (px, mm)\n"
    "  detect          search a map's tiles for objects with a YOLO model (ONNX)\n"
    "  detections-pack a map's detections as 24-byte records for an acoustic modem (and --decode)\n"
    "  training-data   reviewed missions' windows with YOLO labels, to fine-tune the recogniser\n"
    "  review          a simulated survey's truth as the operator's review of a map (for training)\n"
    "\n"
    "Run 'seamap <command> --help' for a command's options.\n";

}  // namespace

int main(int argc, char** argv) {
  using namespace seamap::cli;
  // Every frame allocates and frees the same few large buffers; glibc would
  // return them to the kernel each time and fault them back in on the next
  // frame, doubling the cost of the per-frame stages.
  mallopt(M_MMAP_THRESHOLD, 64 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h")) {
    std::fputs(kUsage, argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  const std::string command = argv[1];
  try {
    if (command == "simulate") return RunSimulate(argc, argv, 2);
    if (command == "build") return RunBuild(argc, argv, 2);
    if (command == "info") return RunInfo(argc, argv, 2);
    if (command == "enhance") return RunEnhance(argc, argv, 2);
    if (command == "enhance-report") return RunEnhanceReport(argc, argv, 2);
    if (command == "serve") return RunServe(argc, argv, 2);
    if (command == "replay") return RunReplay(argc, argv, 2);
    if (command == "export") return RunExport(argc, argv, 2);
    if (command == "trajectory") return RunTrajectory(argc, argv, 2);
    if (command == "trajectory-eval") return RunTrajectoryEval(argc, argv, 2);
    if (command == "simulate-stereo") return RunSimulateStereo(argc, argv, 2);
    if (command == "stereo-model") return RunStereoModel(argc, argv, 2);
    if (command == "stereo-locate") return RunStereoLocate(argc, argv, 2);
    if (command == "stereo-points") return RunStereoPoints(argc, argv, 2);
    if (command == "georef") return RunGeoref(argc, argv, 2);
    if (command == "simulate-buoy") return RunSimulateBuoy(argc, argv, 2);
    if (command == "georef-eval") return RunGeorefEval(argc, argv, 2);
    if (command == "map-eval") return RunMapEval(argc, argv, 2);
    if (command == "detect") return RunDetect(argc, argv, 2);
    if (command == "detections-pack") return RunDetectionsPack(argc, argv, 2);
    if (command == "training-data") return RunTrainingData(argc, argv, 2);
    if (command == "review") return RunReview(argc, argv, 2);
  } catch (const seamap::InputError& e) {
    std::fprintf(stderr, "seamap %s: error: %s\n", command.c_str(), e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    // The readers check declared counts against file sizes; this is the last line.
    std::fprintf(stderr, "seamap %s: error: out of memory: an input asks for more than this machine holds\n",
                 command.c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "seamap %s: failed: %s\n", command.c_str(), e.what());
    return 1;
  }
  std::fprintf(stderr, "seamap: unknown command '%s'\n\n%s", command.c_str(), kUsage);
  return 2;
}
