// seamap stereo-model: an object model from stereo overview pairs.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "cli/args.h"
#include "cli/commands.h"
#include "cli/enhance_setup.h"
#include "core/stereo/object_frame.h"
#include "core/stereo/object_model.h"
#include "core/stereo/stereo_enhancement.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kUsage = R"(usage: seamap stereo-model --calib stereo.yaml --pairs DIR --out object.json [options]
Builds the object's 3D model (points with SIFT descriptors) from overview stereo pairs, in the
left camera frame of the first pair (x right, y down, z forward, metres).
  --calib FILE       OpenCV stereo calibration: K1 D1 K2 D2 R T, image_width image_height
  --pairs DIR        NAME_left.png + NAME_right.png, or left/ + right/ (sorted by NAME)
  --out FILE         the model (object.json)
  --name NAME        the object's class name (default: the --pairs folder's parent folder name)
  --object-frame CSV the object's drawing frame: name,x,y,z,u_left,v_left[,u_right,v_right]
                     (metres; pixels in the first overview pair)
  --no-bundle        skip the bundle adjustment over the overview pairs
  --max-features N   SIFT keypoints per image (default 4000)
  --contrast T       SIFT contrast threshold (default 0.02)
  --feature-enhance off|auto|LIST  enhance the pairs before their features are detected (seed 004;
                     auto keeps the chain that raises the left/right inliers, if any; default off)
)";

}  // namespace

int RunStereoModel(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help", "no-bundle"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  const std::string calib_path = args.Require("calib"), pairs_dir = args.Require("pairs"), out = args.Require("out");
  ModelBuildOptions options;
  options.bundle = !args.Flag("no-bundle");
  options.sift.max_features = args.GetInt("max-features", options.sift.max_features);
  options.sift.contrast_threshold = args.GetDouble("contrast", options.sift.contrast_threshold);
  const FeatureEnhanceOptions feature_enhance = ReadFeatureEnhance(args);
  std::string name = args.GetOr("name", "");
  const std::string frame_csv = args.GetOr("object-frame", "");
  args.RejectUnknown();
  if (!args.positionals().empty())
    throw InputError("", 0, args.positionals()[0], "unexpected argument; see seamap stereo-model --help");
  if (name.empty()) {
    const std::filesystem::path p = std::filesystem::absolute(pairs_dir).lexically_normal();
    name = (p.has_filename() ? p : p.parent_path()).parent_path().filename().string();
    if (name.empty()) name = "object";
  }
  const StereoCalibration calibration = LoadStereoCalibration(calib_path);
  std::vector<LoadedPair> pairs;
  for (const PairFiles& f : ListStereoPairs(pairs_dir))
    pairs.push_back(LoadStereoPair(f, calibration.image_size, calib_path));
  // Read before the long part, so that a bad file fails at once.
  const std::vector<ObjectFramePoint> frame_points =
      frame_csv.empty() ? std::vector<ObjectFramePoint>{} : ReadObjectFramePoints(frame_csv);
  const EnhancementChoice enhancement =
      ChooseStereoEnhancement(feature_enhance, pairs, calibration, options.sift, options.match);
  options.sift.enhance = enhancement.chain;
  if (feature_enhance.spec != "off") {
    std::printf("feature enhancement (%s): %s\n", feature_enhance.spec.c_str(), enhancement.chain.Names().c_str());
    for (const EnhancementTrial& t : enhancement.trials)
      std::printf("  %-40s %7.1f stereo inliers/pair\n", t.chain.c_str(), t.inliers);
  }
  ModelBuildReport report;
  ObjectModel model = BuildObjectModel(pairs, calibration, name, options, &report);
  if (!frame_csv.empty()) {
    const ObjectFrameFit fit = FitObjectFrame(frame_points, calibration, frame_csv);
    for (size_t k = 0; k < frame_points.size(); ++k)
      std::printf("  %s: %.1f mm\n", frame_points[k].name.c_str(), 1000 * fit.residual_m[k]);
    std::printf("object frame from %zu points: RMS %.1f mm\n", frame_points.size(), 1000 * fit.rms_m);
    MoveModel(&model, fit.drawing_from_model);
  }
  std::ofstream file(out);
  if (!file) throw InputError(out, 0, "--out", "cannot write the model");
  file << ModelToJson(model).dump() << "\n";
  for (const std::string& line : report.lines) std::printf("  %s\n", line.c_str());
  std::printf("model '%s': %zu points from %d pairs, bundle RMS %.2f px, %.1f s -> %s\n", model.name.c_str(),
              model.points.size(), report.pairs, report.bundle_rms_px, report.seconds, out.c_str());
  return 0;
}

}  // namespace seamap::cli
