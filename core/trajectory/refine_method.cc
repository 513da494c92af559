#include "core/trajectory/refine_method.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace seamap {

ReliefChoice ChooseRefineMethod(const std::vector<FrameSpec>& frames, const std::vector<double>& times_s,
                                const ReliefChoiceOptions& options) {
  ReliefChoice choice;
  std::vector<double> seabed_up_m, time_s, altitudes;
  for (size_t i = 0; i < frames.size() && i < times_s.size(); ++i) {
    const VehiclePose& p = frames[i].pose;
    if (!(p.altitude_m > 0) || !std::isfinite(p.altitude_m) || !std::isfinite(p.depth_m)) continue;
    seabed_up_m.push_back(-(p.depth_m + p.altitude_m));
    time_s.push_back(times_s[i]);
    altitudes.push_back(p.altitude_m);
  }
  const size_t n = seabed_up_m.size();
  if (n < 10) return choice;
  std::nth_element(altitudes.begin(), altitudes.begin() + n / 2, altitudes.end());
  choice.altitude_m = altitudes[n / 2];
  // Each height against the line fitted to its neighbours within the window
  // (a line, so that a slope of the site is not relief, also at the survey's
  // ends); times relative to the frame's own, for precision on long dives.
  double sum = 0, sum_sq = 0;
  size_t begin = 0, end = 0;
  for (size_t i = 0; i < n; ++i) {
    while (end < n && time_s[end] <= time_s[i] + options.window_s) ++end;
    while (time_s[begin] < time_s[i] - options.window_s) ++begin;
    double s1 = 0, st = 0, stt = 0, sz = 0, stz = 0;
    for (size_t k = begin; k < end; ++k) {
      const double t = time_s[k] - time_s[i], z = seabed_up_m[k] - seabed_up_m[i];
      s1 += 1;
      st += t;
      stt += t * t;
      sz += z;
      stz += t * z;
    }
    const double det = s1 * stt - st * st;
    const double local = det > 1e-9 * s1 * s1 ? (stt * sz - st * stz) / det : sz / s1;  // the line at t = 0
    sum += local;
    sum_sq += local * local;
  }
  choice.relief_rms_m = std::sqrt(std::max(0.0, sum_sq / n - (sum / n) * (sum / n)));
  choice.method = *choice.relief_rms_m > options.min_relief_share * choice.altitude_m ? RefineMethod::kBundle
                                                                                      : RefineMethod::kPlanar;
  if (choice.method == RefineMethod::kBundle && options.max_bundle_frames > 0 &&
      frames.size() > static_cast<size_t>(options.max_bundle_frames)) {
    choice.bundle_window_frames = options.bundle_window_frames;
    char note[256];
    std::snprintf(note, sizeof note,
                  "relief %.3f m rms under the track; %zu frames, more than %d: solved in windows of %d frames "
                  "(--bundle-window)",
                  *choice.relief_rms_m, frames.size(), options.max_bundle_frames, options.bundle_window_frames);
    choice.note = note;
  }
  return choice;
}

}  // namespace seamap
