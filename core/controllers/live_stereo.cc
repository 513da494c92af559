#include "core/controllers/live_stereo.h"

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <mutex>
#include <numeric>
#include <optional>
#include <thread>
#include <utility>

#include <opencv2/core.hpp>

#include "core/controllers/stereo_locate.h"
#include "core/nav/nav_series.h"
#include "core/nav/nav_table.h"

namespace seamap {

struct LiveStereo::State {
  StereoLocateOptions options;
  StereoCalibration calibration;
  ObjectModel model;
  std::vector<PairFiles> files;
  std::vector<StereoSighting> sightings;  // pair order, as the folder lists them
  std::vector<size_t> by_time;            // sightings indices by time
  size_t next = 0;                        // by_time[next] is the first pair not yet due
  std::vector<NavRecord> poses;           // the frames placed so far, by time
  std::optional<LocalFrame> frame;
  Found found;

  std::mutex mutex;
  std::condition_variable wake;
  std::deque<std::pair<size_t, VehiclePose>> queue;
  bool finishing = false, stop = false;
  std::thread worker;

  void Work();
  std::vector<Detection> ObjectsLocked() const;
  std::string UncertaintyLocked(const Detection& object) const;
};

LiveStereo::LiveStereo(const StereoLocateOptions& options) : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.options = options;
  auto rig = LoadStereoRig(s.options);
  s.calibration = std::move(rig.first);
  s.model = std::move(rig.second);
  s.files = ListStereoPairs(s.options.pairs_dir);
  s.sightings = TimedSightings(s.options, s.files);
  s.by_time.resize(s.sightings.size());
  std::iota(s.by_time.begin(), s.by_time.end(), 0);
  std::stable_sort(s.by_time.begin(), s.by_time.end(),
                   [&](size_t a, size_t b) { return *s.sightings[a].time_s < *s.sightings[b].time_s; });
}

LiveStereo::~LiveStereo() {
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    state_->stop = true;
  }
  state_->wake.notify_all();
  if (state_->worker.joinable()) state_->worker.join();
}

int LiveStereo::pairs() const {
  return static_cast<int>(state_->sightings.size());
}

const std::string& LiveStereo::model_name() const {
  return state_->model.name;
}

std::string LiveStereo::model_file() const {
  return std::filesystem::path(state_->options.model_path).filename().string();
}

void LiveStereo::Start(const LocalFrame& frame, Found found) {
  state_->frame.emplace(frame);
  state_->found = std::move(found);
  state_->worker = std::thread([s = state_.get()] { s->Work(); });
}

void LiveStereo::OnFramePlaced(const FrameRecord& frame) {
  if (frame.status != "used" || !frame.time_s || !state_->frame) return;
  VehiclePose pose;
  const LocalXY xy = state_->frame->FromLatLon(frame.position);
  pose.east_m = xy.east, pose.north_m = xy.north;
  pose.altitude_m = frame.altitude_m, pose.depth_m = frame.depth_m;
  pose.heading_deg = frame.heading_deg, pose.pitch_deg = frame.pitch_deg, pose.roll_deg = frame.roll_deg;
  OnFramePlaced(*frame.time_s, pose);
}

void LiveStereo::OnFramePlaced(double time_s, const VehiclePose& pose) {
  if (!std::isfinite(time_s)) return;
  State& s = *state_;
  std::lock_guard<std::mutex> lock(s.mutex);
  const auto by_time = [](double t, const NavRecord& r) { return t < *r.time_s; };
  NavRecord record;
  record.time_s = time_s;
  record.pose = pose;
  // Frames come in time order; one that does not is put in its place.
  s.poses.insert(std::upper_bound(s.poses.begin(), s.poses.end(), time_s, by_time), record);
  const double first = *s.poses.front().time_s, last = *s.poses.back().time_s;
  bool queued = false;
  for (; s.next < s.by_time.size(); ++s.next) {
    StereoSighting& sighting = s.sightings[s.by_time[s.next]];
    const double t = *sighting.time_s;
    if (t > last) break;  // not reached yet
    if (t < first) {
      sighting.skipped = cv::format("at %.3f s, before the first frame (%.3f s)", t, first);
      continue;
    }
    // The pose between the two frames around t: the trajectory so far.
    const auto after = std::upper_bound(s.poses.begin(), s.poses.end(), t, by_time);
    std::vector<NavRecord> around;
    if (after != s.poses.begin()) around.push_back(*(after - 1));
    if (after != s.poses.end()) around.push_back(*after);
    const std::optional<VehiclePose> at = NavSeries(around).PoseAt(t);
    if (!at) continue;  // cannot happen inside [first, last]
    s.queue.emplace_back(s.by_time[s.next], *at);
    queued = true;
  }
  if (queued) s.wake.notify_all();
}

std::vector<Detection> LiveStereo::State::ObjectsLocked() const {
  return StereoObjectDetections(options, sightings, model.name, *frame);
}

std::string LiveStereo::State::UncertaintyLocked(const Detection& d) const {
  // How far the sightings lie from the object's mean (the trajectory's error
  // between them plus the stereo's), and the stereo's own sigma.
  int n = 0;
  double spread2 = 0, worst = 0, sigma2 = 0;
  for (const StereoSighting& s : sightings) {
    if (!s.placed) continue;
    const double distance =
        std::hypot(s.placed->local.east - (*d.position_m)[0], s.placed->local.north - (*d.position_m)[1]);
    if (distance > 1.0) continue;  // another object (the grouping's 1 m)
    ++n, spread2 += distance * distance, worst = std::max(worst, distance);
    sigma2 += s.result.point_sigma_m * s.result.point_sigma_m;
  }
  if (n == 0) return "";
  return cv::format("%d sighting%s, spread %.1f mm RMS (max %.1f mm), stereo sigma %.2f mm", n, n == 1 ? "" : "s",
                    1000 * std::sqrt(spread2 / n), 1000 * worst, 1000 * std::sqrt(sigma2 / n));
}

void LiveStereo::State::Work() {
  for (;;) {
    std::pair<size_t, VehiclePose> job;
    {
      std::unique_lock<std::mutex> lock(mutex);
      wake.wait(lock, [&] { return stop || finishing || !queue.empty(); });
      if (stop || queue.empty()) return;  // stopped, or finishing with nothing left
      job = queue.front();
      queue.pop_front();
    }
    LocateResult result;
    std::optional<PlacedObject> placed;
    try {
      // One pair in memory at a time, as stereo-locate's dive.
      const std::vector<LoadedPair> pair = {
          LoadStereoPair(files[job.first], calibration.image_size, options.calib_path)};
      result = LocateStereoPairs(options, model, calibration, pair);
      if (result.found) placed = PlaceObject(result.object_from_camera, options.mount, job.second, *frame);
    } catch (const std::exception& e) {  // an unreadable pair is a pair not found, said why
      result = LocateResult{};
      result.reason = e.what();
    }
    std::vector<Detection> objects;
    {
      std::lock_guard<std::mutex> lock(mutex);
      StereoSighting& s = sightings[job.first];
      s.result = std::move(result);
      s.placed = placed;
      if (placed) objects = ObjectsLocked();
    }
    if (placed && found) found(std::move(objects));
  }
}

LiveStereoSummary LiveStereo::Finish() {
  State& s = *state_;
  {
    std::lock_guard<std::mutex> lock(s.mutex);
    const double last = s.poses.empty() ? NAN : *s.poses.back().time_s;
    for (; s.next < s.by_time.size(); ++s.next) {
      StereoSighting& sighting = s.sightings[s.by_time[s.next]];
      sighting.skipped = s.poses.empty()
                             ? std::string("no frame was placed")
                             : cv::format("at %.3f s, after the last frame (%.3f s)", *sighting.time_s, last);
    }
    s.finishing = true;
  }
  s.wake.notify_all();
  if (s.worker.joinable()) s.worker.join();
  std::lock_guard<std::mutex> lock(s.mutex);
  LiveStereoSummary summary;
  for (const StereoSighting& x : s.sightings) {
    ++summary.pairs;
    if (!x.skipped.empty()) {
      ++summary.skipped;
      summary.lines.push_back(x.pair + ": skipped, " + x.skipped);
    } else if (!x.placed) {
      ++summary.not_found;
      summary.lines.push_back(cv::format("%s at %.3f s: not found (%s)", x.pair.c_str(), *x.time_s,
                                         x.result.reason.empty() ? "not searched" : x.result.reason.c_str()));
    } else {
      ++summary.found;
      summary.lines.push_back(
          cv::format("%s at %.3f s: '%s' at %.7f %.7f, %.3f m deep, heading %.2f deg (points "
                     "sigma %.2f mm)",
                     x.pair.c_str(), *x.time_s, s.model.name.c_str(), x.placed->position.lat, x.placed->position.lon,
                     x.placed->depth_m, x.placed->heading_deg, 1000 * x.result.point_sigma_m));
    }
  }
  if (s.frame)
    for (const Detection& d : s.ObjectsLocked())
      summary.lines.push_back(cv::format("object '%s' at %.7f %.7f, %.3f m deep: ", d.class_name.c_str(),
                                         d.position.lat, d.position.lon, d.depth_m.value_or(0)) +
                              s.UncertaintyLocked(d));
  return summary;
}

}  // namespace seamap
