// seamap simulate-stereo: a virtual subsea object seen by a stereo rig, with exact truth.
#include <cstdio>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/sim/stereo_survey.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kUsage = R"(usage: seamap simulate-stereo --out DIR [options]
Renders stereo.yaml, overview/ and approach/ pairs (NAME_left.png, NAME_right.png),
empty/ (a pair without the object), truth/poses.json, truth/check_points.csv, scene.json,
and motion.json (the approach pairs' poses as the vehicle's navigation measures them, for
stereo-locate --motion).
  --out DIR        output folder (must be empty unless --force)
  --force          replace a previous scene in DIR
  --seed N         scene layout, poses and noise (default 1)
  --views N        overview pairs and approach pairs (default 3)
  --texture T      object texture: 1 fouled steel (default), 0.15 plain paint, 0 flat
  --haze BETA      water attenuation per metre (default 0.12)
  --noise SIGMA    sensor noise, 8-bit units (default 1.5)
  --blur SIGMA_PX  optical blur (default 0)
  --offset M       first approach pair within M of the object's axis (default 1)
  --supersample S  S x S samples per pixel (default 2)
  --motion-noise M,DEG  navigation noise per axis in motion.json (default 0.001,0.01)
  --dive N         also a dive: N passes over the object, a pair each (dive/dive_SSSS.SSS_left.png:
                   named by its time), the vehicle's trajectory dive/nav.csv (origin 43.1,131.9, seabed
                   30 m deep), one more pair after it ends, and truth/dive.json (the object on the
                   Earth); for stereo-locate --pairs DIR/dive --nav DIR/dive/nav.csv (default 0)
)";

}  // namespace

int RunSimulateStereo(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"force", "help"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  StereoSurveyOptions o;
  o.out_dir = args.Require("out");
  o.force = args.Flag("force");
  o.seed = SeedArg(args);
  o.views = args.GetInt("views", o.views);
  o.object_texture = args.GetDouble("texture", o.object_texture);
  o.render.beta_per_m = args.GetDouble("haze", o.render.beta_per_m);
  o.render.noise_sigma = args.GetDouble("noise", o.render.noise_sigma);
  o.render.blur_sigma_px = args.GetDouble("blur", o.render.blur_sigma_px);
  o.render.supersample = args.GetInt("supersample", o.render.supersample);
  o.approach_offset_m = args.GetDouble("offset", o.approach_offset_m);
  o.dive_sightings = args.GetInt("dive", 0);
  if (const auto noise = args.Get("motion-noise")) {
    char tail = 0;
    if (std::sscanf(noise->c_str(), "%lf,%lf%c", &o.motion_sigma_m, &o.motion_sigma_deg, &tail) != 2)
      throw InputError("", 0, "--motion-noise", "expected M,DEG (metres and degrees per axis), got '" + *noise + "'");
  }
  args.RejectUnknown();
  if (!args.positionals().empty())
    throw InputError("", 0, args.positionals()[0], "unexpected argument; see seamap simulate-stereo --help");
  const StereoSurveySummary s = SimulateStereoSurvey(o);
  std::printf("simulated %zu overview and %zu approach pairs%s (%s), %.1f s -> %s\n", s.overview.size(),
              s.approach.size(),
              o.dive_sightings ? (", a dive of " + std::to_string(o.dive_sightings) + " sightings").c_str() : "",
              s.layout.c_str(), s.seconds, o.out_dir.c_str());
  return 0;
}

}  // namespace seamap::cli
