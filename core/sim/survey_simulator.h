#pragma once
// `seamap simulate`: renders a complete test survey with exact ground truth.
// Output folder layout:
//   photo/frame_000000.png ...   the frames (png or jpg, 8 or 16 bit, gray or BGR)
//   nav.csv                      navigation as reported (with the requested errors)
//   nav_truth.csv                exact poses; both with the header
//     image,time_s,x_m,y_m,altitude_m,depth_m,heading_deg,pitch_deg,roll_deg
//   camera.json                  SaveCameraJson
//   truth/texture.png, truth/texture.json   the seabed and its georeference
//   truth/objects.csv, truth/objects.json   objects on the seabed (with `objects` > 0)
//   truth/terrain.tif            the seabed's heights (with relief > 0): float32
//                                GeoTIFF, metres up from the sea surface, local tmerc
//   survey.json                  origin, every parameter used, frame count, seed
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/camera/camera_model.h"
#include "core/geo/lat_lon.h"
#include "core/sim/frame_renderer.h"
#include "core/sim/seabed_relief.h"
#include "core/sim/survey_path.h"

namespace seamap {

// The seed paper's camera: 696x520 (ICX285 binned 2x2, 12.9 um pitch),
// f = 8 mm (fx ~ 620 px), with mild barrel distortion (k1 -0.05, k2 0.01).
CameraModel DefaultSimCamera();

// A frame rendered at a given pose (simulate --path with a navigation log)
// and named as the log names it: a plain file name whose extension (.png,
// .jpg, .jpeg) gives the format.
struct PosedFrame {
  std::string image;
  TimedPose pose;
  int line = 0;  // in path_file, for messages
};

struct SimulationOptions {
  std::string out_dir;
  bool force = false;  // allow a non-empty out_dir (our previous outputs are replaced)
  uint64_t seed = 1;
  LatLon origin{43.1, 131.9};
  CameraModel camera = DefaultSimCamera();
  bool color = false;
  std::string image_format = "png";  // png | jpg
  int jpeg_quality = 92;
  int bit_depth = 8;         // 8 | 16 (png only)
  std::string texture_file;  // empty: procedural seabed
  double texture_res_m = 0;  // 0: 0.55 x the frame GSD at the lowest altitude
  std::string path_file;     // empty: lawnmower
  // Not empty: one frame at each of these poses (path_file the log they came
  // from; origin its local frame's) instead of a path sampled in time; the
  // trajectory options and line geometry are then unused.
  std::vector<PosedFrame> posed_frames;
  int objects = 0;  // objects painted on the seabed (seabed_objects.h)
  // Their classes in turn (SimulatedObjectClasses ids); empty: the shipped five, as before.
  std::vector<int> object_classes;
  double bury_fraction = 0;  // of every object's height under sediment (--bury, 0-0.8)
  int clutter = 0;           // hard negatives painted beside the objects (--clutter)
  double line_length_m = 10;
  double line_spacing_m = 0;  // 0: 0.7 x the footprint width at the lowest altitude
  TrajectoryOptions trajectory;
  NavErrorOptions nav_errors;
  Degradations degradations;
  // Relief (rms > 0): frames are ray-cast onto it; the vehicle keeps its
  // depth (sea_depth - altitude setpoint, following the mean seabed) and
  // nav altitude_m is what a DVL measures over the relief
  // (core/terrain/dvl_altitude.h).
  SeabedReliefOptions relief;
};

struct SimulationSummary {
  int frames = 0;
  double path_length_m = 0;
  double line_spacing_m = 0;  // 0 for a custom path
  double area_m2 = 0;         // bounding box of all footprints
  cv::Size texture_size;
  double texture_res_m = 0;
  double relief_rms_m = 0;
  double min_clearance_m = 0;  // relief: least height of the vehicle or camera above the seabed near it
  double seconds = 0;
};

// Throws InputError naming the parameter (or file) for invalid options, a
// non-empty output folder without `force`, or files that cannot be written.
// `progress(done, total)` is called from the calling thread as frames are written.
SimulationSummary SimulateSurvey(const SimulationOptions& options, const std::function<void(int, int)>& progress = {});

}  // namespace seamap
