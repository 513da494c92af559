// seamap simulate: renders a test survey with exact ground truth.
#include <cstdio>
#include <optional>
#include <sstream>
#include <vector>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/mosaic/build_config.h"
#include "core/nav/column_aliases.h"
#include "core/nav/csv_table.h"
#include "core/nav/nav_reader.h"
#include "core/sim/seabed_objects.h"
#include "core/sim/survey_simulator.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap::cli {
namespace {

const char* kUsage = R"(usage: seamap simulate --out DIR [options]
Renders a survey (photo/, nav.csv, nav_truth.csv, camera.json, truth/, survey.json).
  --out DIR               output folder (must be empty unless --force)
  --force                 replace the outputs of a previous run in DIR
  --seed N                random seed (default 1); same seed, same survey
  --origin LAT,LON        local frame origin (default 43.1,131.9)
path:
  --frames N              number of frames (default 400)
  --fps F                 frame rate (default 5)
  --speed V               m/s (default 0.5)
  --line-length M         lawnmower line length (default 10)
  --line-spacing M        default 0.7 x the footprint width at --altitude-min
  --path FILE             custom path: CSV with header x_m,y_m (waypoints); or a navigation log that
                          names images (any format build --nav reads, through --config's navigation
                          object): one frame at each of its poses, named as it names them
  --config FILE           a build config: its navigation object reads the --path log
  --altitude-min M, --altitude-max M   (default 1.6, 2.0)
  --pitch-amp DEG, --roll-amp DEG      attitude oscillations (default 3, 2)
  --sea-depth M           depth_m = sea depth - altitude (default 35)
camera and images:
  --width PX --height PX --focal-mm MM --pixel-pitch-um UM   (default 696 520 8 12.9)
  --distortion K1,K2[,P1,P2,K3]        (default -0.05,0.01)
  --color                 BGR frames (default gray)
  --image-format png|jpg  (default png)   --jpeg-quality Q (default 92)
  --bit-depth 8|16        (default 8; 16 needs png)
  --texture FILE          seabed image instead of the procedural one
  --texture-res M         metres per texture pixel (default 0.55 x the GSD at --altitude-min)
  --relief M              rugged seabed: smooth random relief of M metres rms, wavelengths 0.5-4 m (default 0,
                          flat); frames ray-cast onto it, nav altitude_m as a 4-beam DVL measures it,
                          truth/terrain.tif the true heights (float32 GeoTIFF, metres up from the sea surface)
  --relief-texture FILE   the relief from a gray image of heights (8/16-bit PNG or float TIFF) stretched
                          over the seabed and scaled to --relief M rms
  --objects N             paint N objects (tyre, crate, pipe, anchor, rock) on the seabed, >= 1 m apart;
                          truth in truth/objects.csv and truth/objects.json (default 0)
  --object-classes LIST   the objects' classes in turn, of tyre,crate,pipe,anchor,rock,drum (default the
                          first five: the same survey as without it); drum: 0.6 x 0.9 m, lying or standing
  --bury F                every object's lowest fraction F (0-0.8) of its height under sediment
  --clutter N             N look-alikes that are no object (rock rings, pipe pieces, dark rocks), listed
                          under "negatives" in truth/objects.json, not in objects.csv
degradations (off by default):
  --vignetting S --color-cast S --haze S (0-1)   --noise SIGMA (8-bit units)
  --degrade               all of them, moderate (0.6, 0.6, 0.4, 2); explicit values win
  --blur PX               motion blur PX pixels long along the image rows (default 0; not in --degrade)
navigation errors in nav.csv (nav_truth.csv stays exact):
  --nav-noise SIGMA_M     --heading-noise DEG     --nav-drift M_PER_MIN
  --quiet                 no progress bar
)";

std::vector<double> ParseList(const std::string& text, const std::string& param) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || *end != '\0')
      throw InputError("", 0, "--" + param, "expected comma-separated numbers, got '" + text + "'");
    values.push_back(v);
  }
  return values;
}

// A --path file whose header (through the column map) has an image column is
// a navigation log, not waypoints.
bool NamesImages(const std::string& path, const NavReadOptions& nav) {
  const std::vector<TextLine> lines = ReadTextLines(path);
  const CsvTable header = ParseCsv({lines.front()}, path);
  return MapColumns(header.header, nav.columns, path, header.header_line).Has("image");
}

// The log's records as frames to render; its warnings and skipped lines go to
// standard error, as build reports them.
void ReadPosedFrames(const std::string& path, const NavReadOptions& nav_options, SimulationOptions* o) {
  const NavTable nav = ReadNavigation(path, nav_options);
  for (const auto& w : nav.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  for (const auto& r : nav.rejected) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
  o->origin = nav.origin;
  for (size_t i = 0; i < nav.records.size(); ++i) {
    const NavRecord& r = nav.records[i];
    if (r.image.empty()) continue;  // a time series denser than the photos
    const double time_s = r.time_s.value_or(static_cast<double>(i) / o->trajectory.fps);
    o->posed_frames.push_back({r.image, {time_s, r.pose}, r.line});
  }
  if (o->posed_frames.empty()) throw InputError(path, 0, "image", "no line of the navigation log names an image");
}

SimulationOptions ParseOptions(Args& args) {
  SimulationOptions o;
  o.out_dir = args.Require("out");
  o.force = args.Flag("force");
  o.seed = SeedArg(args);
  if (auto origin = args.Get("origin")) {
    const LatLonArg ll = ParseLatLon(*origin, "--origin");
    o.origin = {ll.lat, ll.lon};
  }

  TrajectoryOptions& t = o.trajectory;
  t.frames = args.GetInt("frames", t.frames);
  t.fps = args.GetDouble("fps", t.fps);
  t.speed_mps = args.GetDouble("speed", t.speed_mps);
  t.altitude_min_m = args.GetDouble("altitude-min", t.altitude_min_m);
  t.altitude_max_m = args.GetDouble("altitude-max", t.altitude_max_m);
  t.pitch_amp_deg = args.GetDouble("pitch-amp", t.pitch_amp_deg);
  t.roll_amp_deg = args.GetDouble("roll-amp", t.roll_amp_deg);
  t.sea_depth_m = args.GetDouble("sea-depth", t.sea_depth_m);
  o.line_length_m = args.GetDouble("line-length", o.line_length_m);
  o.line_spacing_m = args.GetDouble("line-spacing", o.line_spacing_m);
  if (args.Get("line-spacing") && !(o.line_spacing_m > 0))
    throw InputError("", 0, "--line-spacing", "expected a positive spacing in metres");
  o.path_file = args.GetOr("path", "");
  NavReadOptions nav_options;
  if (auto config = args.Get("config")) nav_options = LoadBuildConfig(*config).nav;
  if (auto origin = args.Get("origin")) {
    const LatLonArg ll = ParseLatLon(*origin, "--origin");
    nav_options.origin = LatLon{ll.lat, ll.lon};
  }
  if (!o.path_file.empty() && NamesImages(o.path_file, nav_options)) ReadPosedFrames(o.path_file, nav_options, &o);
  o.objects = args.GetInt("objects", 0);
  o.relief.rms_m = args.GetDouble("relief", 0);
  o.relief.texture_file = args.GetOr("relief-texture", "");
  if (o.objects < 0) throw InputError("", 0, "--objects", "expected a number of objects >= 0");
  if (auto classes = args.Get("object-classes")) o.object_classes = ParseObjectClasses(*classes, "--object-classes");
  o.bury_fraction = args.GetDouble("bury", 0);
  o.clutter = args.GetInt("clutter", 0);

  const int width = args.GetInt("width", 696), height = args.GetInt("height", 520);
  if (width <= 0) throw InputError("", 0, "--width", "expected a positive number of pixels");
  if (height <= 0) throw InputError("", 0, "--height", "expected a positive number of pixels");
  const double focal_mm = args.GetDouble("focal-mm", 8.0);
  const double pitch_um = args.GetDouble("pixel-pitch-um", 12.9);
  if (!(focal_mm > 0)) throw InputError("", 0, "--focal-mm", "expected a positive focal length in mm");
  if (!(pitch_um > 0)) throw InputError("", 0, "--pixel-pitch-um", "expected a positive pixel pitch in um");
  o.camera = CameraFromFocalLength(focal_mm, pitch_um, width, height);
  o.camera.distortion = DefaultSimCamera().distortion;
  if (auto d = args.Get("distortion")) {
    const auto k = ParseList(*d, "distortion");
    if (k.empty() || k.size() > 5) throw InputError("", 0, "--distortion", "expected 1 to 5 numbers: k1,k2,p1,p2,k3");
    o.camera.distortion = {};
    for (size_t i = 0; i < k.size(); ++i) o.camera.distortion[i] = k[i];
  }
  o.color = args.Flag("color");
  o.image_format = args.GetOr("image-format", o.image_format);
  if (o.image_format == "jpeg") o.image_format = "jpg";
  o.jpeg_quality = args.GetInt("jpeg-quality", o.jpeg_quality);
  o.bit_depth = args.GetInt("bit-depth", o.bit_depth);
  o.texture_file = args.GetOr("texture", "");
  o.texture_res_m = args.GetDouble("texture-res", 0);
  if (args.Get("texture-res") && !(o.texture_res_m > 0))
    throw InputError("", 0, "--texture-res", "expected a positive resolution in metres per pixel");

  const Degradations base = args.Flag("degrade") ? Degradations::Moderate() : Degradations{};
  Degradations& d = o.degradations;
  d.vignetting = args.GetDouble("vignetting", base.vignetting);
  d.color_cast = args.GetDouble("color-cast", base.color_cast);
  d.haze = args.GetDouble("haze", base.haze);
  d.noise_sigma = args.GetDouble("noise", base.noise_sigma);
  d.blur_px = args.GetDouble("blur", 0);

  NavErrorOptions& n = o.nav_errors;
  n.position_sigma_m = args.GetDouble("nav-noise", 0);
  n.heading_sigma_deg = args.GetDouble("heading-noise", 0);
  n.drift_m_per_min = args.GetDouble("nav-drift", 0);
  return o;
}

}  // namespace

int RunSimulate(int argc, char** argv, int first) {
  try {
    Args args(argc, argv, first, {"force", "color", "degrade", "quiet", "help"});
    if (args.Flag("help")) {
      std::fputs(kUsage, stdout);
      return 0;
    }
    SimulationOptions options = ParseOptions(args);
    const bool quiet = args.Flag("quiet");
    args.RejectUnknown();
    if (!args.positionals().empty())
      throw InputError("", 0, args.positionals()[0], "unexpected argument; see seamap simulate --help");

    // Created at the first frame: a custom path may hold fewer frames than asked for.
    std::optional<ProgressBar> bar;
    const SimulationSummary s = SimulateSurvey(options, [&](int done, int total) {
      if (!bar) bar.emplace("frames", total, !quiet);
      bar->Update(done);
    });
    if (bar) bar->Finish();
    std::printf("simulated %d frames, %.1f m path, area %.1f m2, texture %dx%d px at %.2f mm/px, %.1f s -> %s\n",
                s.frames, s.path_length_m, s.area_m2, s.texture_size.width, s.texture_size.height,
                s.texture_res_m * 1000, s.seconds, options.out_dir.c_str());
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "seamap simulate: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "seamap simulate: %s\n", e.what());
    return 1;
  }
}

}  // namespace seamap::cli
