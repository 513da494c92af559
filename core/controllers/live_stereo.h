#pragma once
// Stereo pairs located as the dive goes (`seamap replay --stereo DIR`): a
// pair is searched once the frames placed so far span its time, so the pose
// at that time is known (the trajectory the map is painted with: the
// navigation, or the filter's with --nav-mode). The search runs on a worker
// of its own: frame intake never waits for it. Every find hands the objects
// found so far to the caller (one detection per object, as `stereo-locate
// --map` stores them). Pairs before the first frame or after the last are
// skipped; the end's summary says so, and gives each object's sightings,
// their spread and the stereo's own sigma (its uncertainty).
//
// The stereo types stay behind this header (core/controllers/stereo_locate.h
// has them): its users also see the trajectory module's.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/camera/vehicle_pose.h"
#include "core/geo/local_frame.h"
#include "core/tiles/mission_records.h"

namespace seamap {

struct StereoLocateOptions;

// What the dive's pairs gave: a line per pair and per object for the terminal, and the counts.
struct LiveStereoSummary {
  std::vector<std::string> lines;
  int pairs = 0, found = 0, not_found = 0, skipped = 0;
};

class LiveStereo {
 public:
  // Every object found so far, in the mission's frame.
  using Found = std::function<void(std::vector<Detection> objects)>;

  // Loads the calibration and model and lists the pairs with their times
  // (options: pairs_dir, calib_path, model_path, pair_times_path, mount,
  // method, locate): InputError naming what does not fit, before any map is
  // made.
  explicit LiveStereo(const StereoLocateOptions& options);
  ~LiveStereo();  // stops the worker (pairs still queued are left)
  LiveStereo(const LiveStereo&) = delete;
  LiveStereo& operator=(const LiveStereo&) = delete;

  // Starts the worker; objects are placed in `frame` (the mission's local frame).
  void Start(const LocalFrame& frame, Found found);
  // A frame placed with `pose` (in the mission's frame) at `time_s`; pairs
  // whose time the frames now span are queued for the worker.
  void OnFramePlaced(double time_s, const VehiclePose& pose);
  // The same for a frame the map used (its placed pose); rejected frames and
  // frames without a time are left out. After Start.
  void OnFramePlaced(const FrameRecord& frame);
  // The dive has ended: waits for the queued pairs, skips the pairs the
  // frames never reached. Again: the same summary.
  LiveStereoSummary Finish();

  int pairs() const;
  const std::string& model_name() const;
  // The model file's name: the detections' `model`, which a republish replaces.
  std::string model_file() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace seamap
