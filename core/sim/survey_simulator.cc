#include "core/sim/survey_simulator.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>
#include <thread>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/camera/frame_projector.h"
#include "core/sim/seabed_objects.h"
#include "core/sim/seabed_texture.h"
#include "core/terrain/dvl_altitude.h"
#include "core/terrain/height_grid_io.h"
#include "core/util/error.h"

namespace seamap {
namespace fs = std::filesystem;
namespace {

constexpr double kTextureMargin_m = 0.25;  // around the union of footprints
constexpr double kMaxTexturePixels = 1.5e9;

void Require(bool ok, const std::string& param, const std::string& expected) {
  if (!ok) throw InputError("", 0, param, expected);
}

void Validate(const SimulationOptions& o) {
  Require(!o.out_dir.empty(), "--out", "is required: the folder to write the survey to");
  const TrajectoryOptions& t = o.trajectory;
  Require(t.frames > 0, "--frames", "expected a positive number of frames");
  Require(o.objects >= 0, "--objects", "expected a number of objects >= 0");
  Require(o.bury_fraction >= 0 && o.bury_fraction <= 0.8, "--bury",
          "expected the fraction 0-0.8 of each object's height under sediment");
  Require(o.bury_fraction == 0 || o.objects > 0, "--bury", "needs --objects");
  Require(o.clutter >= 0 && o.clutter <= 1000, "--clutter", "expected a number of clutter pieces 0-1000");
  Require(o.object_classes.empty() || o.objects > 0, "--object-classes", "needs --objects");
  Require(t.fps > 0, "--fps", "expected a positive frame rate");
  Require(t.speed_mps > 0, "--speed", "expected a positive speed in m/s");
  Require(t.altitude_min_m > 0, "--altitude-min", "expected a positive altitude in metres");
  Require(t.altitude_max_m >= t.altitude_min_m, "--altitude-max", "expected at least --altitude-min");
  Require(t.pitch_amp_deg >= 0 && t.pitch_amp_deg < 60, "--pitch-amp", "expected 0-60 degrees");
  Require(t.roll_amp_deg >= 0 && t.roll_amp_deg < 60, "--roll-amp", "expected 0-60 degrees");
  Require(o.line_length_m > 0, "--line-length", "expected a positive length in metres");
  Require(o.line_spacing_m >= 0, "--line-spacing", "expected a positive spacing in metres");
  Require(o.texture_res_m >= 0, "--texture-res", "expected a positive resolution in metres per pixel");
  Require(o.image_format == "png" || o.image_format == "jpg", "--image-format", "expected png or jpg");
  Require(o.jpeg_quality >= 1 && o.jpeg_quality <= 100, "--jpeg-quality", "expected 1-100");
  Require(o.bit_depth == 8 || o.bit_depth == 16, "--bit-depth", "expected 8 or 16");
  Require(o.bit_depth == 8 || o.image_format == "png", "--bit-depth",
          "16-bit frames need --image-format png (JPEG is 8-bit)");
  const Degradations& d = o.degradations;
  Require(d.vignetting >= 0 && d.vignetting <= 1, "--vignetting", "expected a strength in 0-1");
  Require(d.color_cast >= 0 && d.color_cast <= 1, "--color-cast", "expected a strength in 0-1");
  Require(d.haze >= 0 && d.haze <= 5, "--haze", "expected a strength in 0-5");
  Require(d.noise_sigma >= 0, "--noise", "expected a non-negative sigma in 8-bit units");
  Require(d.blur_px >= 0 && d.blur_px <= 64, "--blur", "expected a motion blur of 0-64 pixels");
  const NavErrorOptions& n = o.nav_errors;
  Require(n.position_sigma_m >= 0, "--nav-noise", "expected a non-negative sigma in metres");
  Require(n.heading_sigma_deg >= 0, "--heading-noise", "expected a non-negative sigma in degrees");
  Require(n.drift_m_per_min >= 0, "--nav-drift", "expected a non-negative drift in metres per minute");
  o.camera.Validate("camera");
  o.relief.Check();
  std::set<std::string> names;
  for (const PosedFrame& f : o.posed_frames) {
    const std::string where = o.path_file;
    const std::string name = f.image;
    const fs::path as_path(name);
    if (name.empty() || as_path.filename().string() != name || name == "." || name == "..")
      throw InputError(where, f.line, "image",
                       "expected a plain file name (no folder), got '" + name.substr(0, 100) + "'");
    std::string ext = as_path.extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (ext != ".png" && ext != ".jpg" && ext != ".jpeg")
      throw InputError(where, f.line, "image",
                       "expected a .png, .jpg or .jpeg name to render the frame as, got '" + name.substr(0, 100) + "'");
    if (o.bit_depth == 16 && ext != ".png")
      throw InputError(where, f.line, "image",
                       "16-bit frames need .png names (JPEG is 8-bit), got '" + name.substr(0, 100) + "'");
    if (!names.insert(name).second)
      throw InputError(where, f.line, "image", "the image '" + name.substr(0, 100) + "' is named twice");
    if (!(f.pose.pose.altitude_m > 0))
      throw InputError(where, f.line, "altitude_m", "a frame needs an altitude above the seabed > 0");
  }
  Require(o.posed_frames.empty() || o.relief.Flat(), "--relief", "is not available with a navigation log as --path");
}

// Over relief: nav altitude_m (truth and reported) becomes what a DVL
// measures, and the vehicle must stay clear of the seabed.
void MeasureOverRelief(const SimulationOptions& o, const HeightGridRayCaster& terrain, std::vector<TimedPose>* truth,
                       std::vector<TimedPose>* nav, SimulationSummary* summary) {
  constexpr double kMinClearance_m = 0.3, kNeighbourhood_m = 0.5, kStep_m = 0.1;
  double least = INFINITY;
  for (size_t i = 0; i < truth->size(); ++i) {
    VehiclePose& p = (*truth)[i].pose;
    const double vehicle_up = -p.depth_m;
    const Eigen::Vector3d offset = NedFromBody(p) * o.camera.mount_offset_m;
    const double camera_up = vehicle_up - offset.z();
    double highest = -INFINITY;
    for (double de = -kNeighbourhood_m; de <= kNeighbourhood_m + 1e-9; de += kStep_m)
      for (double dn = -kNeighbourhood_m; dn <= kNeighbourhood_m + 1e-9; dn += kStep_m) {
        double h = 0;
        if (terrain.Height(p.east_m + de, p.north_m + dn, &h)) highest = std::max(highest, h);
      }
    const double clearance = std::min(vehicle_up, camera_up) - highest;
    least = std::min(least, clearance);
    if (clearance < kMinClearance_m) {
      char msg[256];
      std::snprintf(msg, sizeof msg,
                    "the seabed rises to %.2f m of the vehicle at frame %zu (%.1f s); keep it %.1f m clear: lower "
                    "--relief or raise --altitude-min",
                    clearance, i, (*truth)[i].time_s, kMinClearance_m);
      throw InputError("", 0, "--relief", msg);
    }
    double altitude = DvlAltitude(terrain, {p.east_m, p.north_m}, vehicle_up, p.heading_deg, p.pitch_deg, p.roll_deg);
    double below = 0;
    if (!std::isfinite(altitude) && terrain.Height(p.east_m, p.north_m, &below)) altitude = vehicle_up - below;
    if (!std::isfinite(altitude))
      throw InputError("", 0, "--relief", "the simulated relief does not reach below frame " + std::to_string(i));
    p.altitude_m = altitude;
    (*nav)[i].pose.altitude_m = altitude;
  }
  summary->min_clearance_m = least;
  summary->relief_rms_m = o.relief.rms_m;
}

// Refuses a non-empty folder unless forced.
void CheckOutput(const SimulationOptions& o) {
  const fs::path out(o.out_dir);
  if (fs::exists(out) && !fs::is_directory(out)) throw InputError(o.out_dir, 0, "--out", "exists and is not a folder");
  if (fs::exists(out) && !fs::is_empty(out) && !o.force)
    throw InputError(o.out_dir, 0, "--out", "folder is not empty; use --force to overwrite it");
}

// Removes only our own previous outputs, then creates the folders.
void PrepareOutput(const SimulationOptions& o) {
  const fs::path out(o.out_dir);
  std::error_code ec;
  if (fs::exists(out) && !fs::is_empty(out)) {
    for (const char* name : {"photo", "truth"}) fs::remove_all(out / name, ec);
    for (const char* name : {"nav.csv", "nav_truth.csv", "camera.json", "survey.json"}) fs::remove(out / name, ec);
  }
  fs::create_directories(out / "photo", ec);
  fs::create_directories(out / "truth", ec);
  if (ec || !fs::is_directory(out / "photo"))
    throw InputError(o.out_dir, 0, "--out", "cannot create the folder: " + ec.message());
}

std::string FrameName(int i, const std::string& ext) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06d.%s", i, ext.c_str());
  return name;
}

// The frames' file names: the log's, or frame_NNNNNN.ext.
std::vector<std::string> FrameNames(const SimulationOptions& o, size_t count) {
  std::vector<std::string> names;
  for (size_t i = 0; i < count; ++i)
    names.push_back(o.posed_frames.empty() ? FrameName(static_cast<int>(i), o.image_format) : o.posed_frames[i].image);
  return names;
}

void WriteNav(const std::string& path, const std::vector<TimedPose>& poses, const std::vector<std::string>& names) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw InputError(path, 0, "", "cannot write the navigation file");
  std::fprintf(f, "image,time_s,x_m,y_m,altitude_m,depth_m,heading_deg,pitch_deg,roll_deg\n");
  for (size_t i = 0; i < poses.size(); ++i) {
    const VehiclePose& p = poses[i].pose;
    std::fprintf(f, "%s,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n", names[i].c_str(), poses[i].time_s, p.east_m,
                 p.north_m, p.altitude_m, p.depth_m, p.heading_deg, p.pitch_deg, p.roll_deg);
  }
  if (std::fclose(f) != 0) throw InputError(path, 0, "", "cannot write the navigation file");
}

void WriteJson(const std::string& path, const nlohmann::json& j) {
  std::ofstream out(path);
  out << j.dump(2) << "\n";
  if (!out) throw InputError(path, 0, "", "cannot write the file");
}

nlohmann::json SurveyJson(const SimulationOptions& o, const SimulationSummary& s) {
  const CameraModel& c = o.camera;
  const TrajectoryOptions& t = o.trajectory;
  const Degradations& d = o.degradations;
  const NavErrorOptions& n = o.nav_errors;
  nlohmann::json j = {
      {"origin", {o.origin.lat, o.origin.lon}},
      {"seed", o.seed},
      {"objects", o.objects},
      {"frames", s.frames},
      {"camera",
       {{"width", c.width},
        {"height", c.height},
        {"fx", c.fx},
        {"fy", c.fy},
        {"cx", c.cx},
        {"cy", c.cy},
        {"distortion", c.distortion}}},
      {"image",
       {{"format", o.image_format}, {"jpeg_quality", o.jpeg_quality}, {"bit_depth", o.bit_depth}, {"color", o.color}}},
      {"path",
       {{"type", !o.posed_frames.empty() ? "poses"
                 : o.path_file.empty()   ? "lawnmower"
                                         : "file"},
        {"file", o.path_file},
        {"line_length_m", o.line_length_m},
        {"line_spacing_m", s.line_spacing_m},
        {"length_m", s.path_length_m}}},
      {"trajectory",
       {{"speed_mps", t.speed_mps},
        {"fps", t.fps},
        {"frames_requested", t.frames},
        {"altitude_min_m", t.altitude_min_m},
        {"altitude_max_m", t.altitude_max_m},
        {"pitch_amp_deg", t.pitch_amp_deg},
        {"roll_amp_deg", t.roll_amp_deg},
        {"sea_depth_m", t.sea_depth_m}}},
      {"texture",
       {{"source", o.texture_file.empty() ? "procedural" : o.texture_file},
        {"res_m", s.texture_res_m},
        {"width", s.texture_size.width},
        {"height", s.texture_size.height}}},
      {"degradations",
       {{"vignetting", d.vignetting}, {"color_cast", d.color_cast}, {"haze", d.haze}, {"noise_sigma", d.noise_sigma}}},
      {"nav_errors",
       {{"position_sigma_m", n.position_sigma_m},
        {"heading_sigma_deg", n.heading_sigma_deg},
        {"drift_m_per_min", n.drift_m_per_min}}},
      {"relief_m", o.relief.rms_m},
      {"area_m2", s.area_m2}};
  // Issue 32's options only when used: a five-class survey's survey.json stays as it was.
  if (!o.object_classes.empty()) {
    std::vector<std::string> names;
    for (int id : o.object_classes) names.push_back(SimulatedObjectClasses().at(id));
    j["object_classes"] = names;
  }
  if (o.bury_fraction > 0) j["bury_fraction"] = o.bury_fraction;
  if (o.clutter > 0) j["clutter"] = o.clutter;
  if (d.blur_px > 0) j["degradations"]["blur_px"] = d.blur_px;
  if (!o.relief.Flat())
    j["relief"] = {{"rms_m", o.relief.rms_m},
                   {"source", o.relief.texture_file.empty() ? "random" : o.relief.texture_file},
                   {"cell_m", o.relief.cell_m},
                   {"min_wavelength_m", o.relief.min_wavelength_m},
                   {"max_wavelength_m", o.relief.max_wavelength_m},
                   {"min_clearance_m", s.min_clearance_m},
                   {"altitude", "DVL: mean vertical range of 4 beams at 30 deg"},
                   {"terrain", "truth/terrain.tif"}};
  return j;
}

}  // namespace

CameraModel DefaultSimCamera() {
  CameraModel c = CameraFromFocalLength(8.0, 12.9, 696, 520);
  c.distortion = {-0.05, 0.01, 0, 0, 0};
  return c;
}

SimulationSummary SimulateSurvey(const SimulationOptions& o, const std::function<void(int, int)>& progress) {
  const auto start = std::chrono::steady_clock::now();
  Validate(o);
  CheckOutput(o);
  const CameraModel& cam = o.camera;
  const TrajectoryOptions& traj = o.trajectory;
  SimulationSummary summary;

  // Path and poses.
  const double needed_m = (traj.frames - 1) * traj.speed_mps / traj.fps;
  SurveyPath path = SurveyPath::FromWaypoints({{0, 0}, {0, 1}});
  std::vector<TimedPose> truth;
  double altitude_min_m = traj.altitude_min_m;
  if (!o.posed_frames.empty()) {
    altitude_min_m = INFINITY;
    for (const PosedFrame& f : o.posed_frames) {
      if (!truth.empty())
        summary.path_length_m +=
            std::hypot(f.pose.pose.east_m - truth.back().pose.east_m, f.pose.pose.north_m - truth.back().pose.north_m);
      truth.push_back(f.pose);
      altitude_min_m = std::min(altitude_min_m, f.pose.pose.altitude_m);
    }
  } else {
    if (o.path_file.empty()) {
      summary.line_spacing_m = o.line_spacing_m > 0 ? o.line_spacing_m : 0.7 * cam.width / cam.fx * traj.altitude_min_m;
      path = SurveyPath::Lawnmower(o.line_length_m, summary.line_spacing_m, needed_m);
    } else {
      path = SurveyPath::LoadCsv(o.path_file);
    }
    summary.path_length_m = path.Length();
    truth = MakeTrajectory(path, traj, o.seed);
  }
  std::vector<TimedPose> nav = AddNavigationErrors(truth, o.nav_errors, o.seed);
  const std::vector<std::string> names = FrameNames(o, truth.size());
  summary.frames = static_cast<int>(truth.size());

  // Texture (and relief) covering every footprint. Over relief the
  // footprints are taken on a plane below the deepest seabed, which contains
  // every ray's first hit; the plane is lowered again should the relief turn
  // out deeper.
  FrameRenderer renderer(cam, o.degradations);
  const bool relief = !o.relief.Flat();
  const double mean_seabed_up_m = -traj.sea_depth_m;
  double below_mean_m = relief ? 3.5 * o.relief.rms_m : 0;
  cv::Rect2d area;
  std::vector<cv::Rect2d> frame_bounds;
  SeabedTexture texture;
  texture.res_m = o.texture_res_m > 0 ? o.texture_res_m : 0.55 * altitude_min_m / cam.fx;
  if (!o.texture_file.empty()) texture.image = LoadTextureImage(o.texture_file, o.color, o.bit_depth);
  cv::Size texture_size;
  HeightGrid terrain;
  for (int attempt = 0;; ++attempt) {
    frame_bounds.clear();
    bool first_bounds = true;
    for (const TimedPose& tp : truth) {
      VehiclePose lowest = tp.pose;
      lowest.altitude_m += below_mean_m;
      cv::Rect2d b;
      if (!renderer.GroundBounds(lowest, &b))
        throw InputError("", 0, "--pitch-amp",
                         "a frame's view does not reach the seabed; reduce "
                         "--pitch-amp/--roll-amp");
      area = first_bounds ? b : (area | b);
      frame_bounds.push_back(b);
      first_bounds = false;
    }
    const double need_w = area.width + 2 * kTextureMargin_m, need_h = area.height + 2 * kTextureMargin_m;
    if (o.texture_file.empty()) {
      texture_size = cv::Size(static_cast<int>(std::ceil(need_w / texture.res_m)),
                              static_cast<int>(std::ceil(need_h / texture.res_m)));
      if (static_cast<double>(texture_size.width) * texture_size.height > kMaxTexturePixels)
        throw InputError("", 0, "--texture-res",
                         "the seabed texture would need " + std::to_string(texture_size.width) + "x" +
                             std::to_string(texture_size.height) +
                             " pixels; use a coarser --texture-res or a shorter survey");
    } else {
      texture_size = texture.image.size();
      const double w = texture.image.cols * texture.res_m, h = texture.image.rows * texture.res_m;
      if (w < need_w || h < need_h) {
        char msg[256];
        std::snprintf(msg, sizeof msg,
                      "covers %.2f x %.2f m at %.5f m/px but the survey needs %.2f x %.2f m; use a "
                      "larger --texture-res or a shorter path",
                      w, h, texture.res_m, need_w, need_h);
        throw InputError(o.texture_file, 0, "--texture", msg);
      }
    }
    // Centre the texture on the surveyed area.
    const double centre_e = area.x + area.width / 2, centre_n = area.y + area.height / 2;
    texture.east_min = centre_e - texture_size.width * texture.res_m / 2;
    texture.north_max = centre_n + texture_size.height * texture.res_m / 2;
    if (!relief) break;
    const double extent_w = texture_size.width * texture.res_m, extent_h = texture_size.height * texture.res_m;
    terrain = MakeSeabedRelief(o.relief, {texture.east_min, texture.north_max - extent_h, extent_w, extent_h},
                               mean_seabed_up_m, o.seed);
    double lowest_m = 0;
    cv::minMaxLoc(terrain.height_m, &lowest_m);
    if (mean_seabed_up_m - lowest_m <= below_mean_m || attempt >= 3) break;
    below_mean_m = mean_seabed_up_m - lowest_m + 0.05;
  }
  summary.area_m2 = area.area();
  if (o.texture_file.empty())
    texture.image = MakeProceduralTexture(texture_size, texture.res_m, o.color, o.bit_depth, o.seed);
  if (relief) {
    renderer.SetTerrain(terrain);
    MeasureOverRelief(o, *renderer.terrain(), &truth, &nav, &summary);
    for (const TimedPose& tp : truth) {
      cv::Rect2d b;
      if (!renderer.GroundBounds(tp.pose, &b))
        throw InputError("", 0, "--relief",
                         "a frame's view leaves the simulated relief; reduce --pitch-amp/--roll-amp");
    }
  }
  // Objects go into the texture before anything is rendered from it.
  std::vector<SeabedObject> objects = PlaceSeabedObjects(o.objects, frame_bounds, o.seed, 1.0, o.object_classes);
  for (SeabedObject& obj : objects) obj.buried_fraction = o.bury_fraction;
  const std::vector<SeabedObject> clutter = PlaceClutter(o.clutter, frame_bounds, o.seed, objects);
  objects.insert(objects.end(), clutter.begin(), clutter.end());
  PaintSeabedObjects(objects, &texture);
  summary.texture_size = texture.image.size();
  summary.texture_res_m = texture.res_m;

  // Small files first, so a bad folder fails fast.
  PrepareOutput(o);
  const fs::path out(o.out_dir);
  SaveCameraJson(cam, (out / "camera.json").string());
  WriteNav((out / "nav.csv").string(), nav, names);
  WriteNav((out / "nav_truth.csv").string(), truth, names);
  if (o.objects > 0 || o.clutter > 0) SaveObjectsTruth(objects, LocalFrame(o.origin), (out / "truth").string());

  // The large truth PNG is encoded while the frames render.
  std::exception_ptr truth_error;
  std::thread truth_writer([&] {
    try {
      SaveTruth(texture, o.origin, (out / "truth").string());
      if (relief) WriteHeightGridGeotiff(terrain, o.origin, (out / "truth" / "terrain.tif").string());
    } catch (...) {
      truth_error = std::current_exception();
    }
  });

  std::vector<int> params;
  if (o.image_format == "jpg" || !o.posed_frames.empty()) params = {cv::IMWRITE_JPEG_QUALITY, o.jpeg_quality};
  std::exception_ptr frame_error;
  std::mutex error_mutex;
  const int total = summary.frames, batch = 16;
  for (int first = 0; first < total; first += batch) {
    const int last = std::min(total, first + batch);
    cv::parallel_for_(cv::Range(first, last), [&](const cv::Range& range) {
      for (int i = range.start; i < range.end; ++i) {
        try {
          const uint64_t noise_seed = o.seed * 1000003ull + static_cast<uint64_t>(i) + 1;
          const cv::Mat frame = renderer.Render(texture, truth[i].pose, noise_seed);
          const std::string file = (out / "photo" / names[i]).string();
          if (!cv::imwrite(file, frame, params)) throw InputError(file, 0, "", "cannot write the frame");
        } catch (...) {
          std::lock_guard<std::mutex> lock(error_mutex);
          if (!frame_error) frame_error = std::current_exception();
        }
      }
    });
    if (frame_error) break;
    if (progress) progress(last, total);
  }
  truth_writer.join();
  if (frame_error) std::rethrow_exception(frame_error);
  if (truth_error) std::rethrow_exception(truth_error);

  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  WriteJson((out / "survey.json").string(), SurveyJson(o, summary));
  return summary;
}

}  // namespace seamap
