#include "core/trajectory/track_pairing.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/nav/nav_values.h"
#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap {
namespace {

std::vector<FramePair> PairByImage(const NavTable& estimate, const NavTable& truth) {
  std::map<std::string, int> by_name;
  for (size_t i = 0; i < estimate.records.size(); ++i)
    if (!estimate.records[i].image.empty()) by_name.emplace(estimate.records[i].image, static_cast<int>(i));
  std::vector<FramePair> pairs;
  for (size_t j = 0; j < truth.records.size(); ++j) {
    auto it = by_name.find(truth.records[j].image);
    if (it == by_name.end()) continue;
    pairs.push_back({it->second, static_cast<int>(j)});
    by_name.erase(it);  // one truth frame per estimate frame
  }
  return pairs;
}

std::vector<FramePair> PairByTime(const NavTable& estimate, const NavTable& truth) {
  std::vector<std::pair<double, int>> times;  // estimate, sorted
  for (size_t i = 0; i < estimate.records.size(); ++i)
    if (estimate.records[i].time_s) times.emplace_back(*estimate.records[i].time_s, static_cast<int>(i));
  std::sort(times.begin(), times.end());
  const double tolerance = TimePairingTolerance(truth);
  std::vector<bool> used(estimate.records.size(), false);
  std::vector<FramePair> pairs;
  for (size_t j = 0; j < truth.records.size(); ++j) {
    if (!truth.records[j].time_s || times.empty()) continue;
    const double t = *truth.records[j].time_s;
    auto it = std::lower_bound(times.begin(), times.end(), std::make_pair(t, -1));
    int best = -1;
    double best_gap = tolerance;
    for (auto c : {it, it == times.begin() ? it : it - 1}) {
      if (c == times.end() || used[c->second]) continue;
      const double gap = std::fabs(c->first - t);
      if (gap <= best_gap) best_gap = gap, best = c->second;
    }
    if (best < 0) continue;
    used[best] = true;
    pairs.push_back({best, static_cast<int>(j)});
  }
  return pairs;
}

std::string FirstImage(const NavTable& table) {
  for (const auto& r : table.records)
    if (!r.image.empty()) return r.image;
  return "";
}

}  // namespace

double TimePairingTolerance(const NavTable& truth) {
  std::vector<double> times, gaps;
  for (const auto& r : truth.records)
    if (r.time_s) times.push_back(*r.time_s);
  std::sort(times.begin(), times.end());
  for (size_t i = 1; i < times.size(); ++i)
    if (times[i] > times[i - 1]) gaps.push_back(times[i] - times[i - 1]);
  if (gaps.empty()) return 0.05;
  return std::min(0.05, 0.25 * Median(gaps));
}

TrackPairing PairFrames(const NavTable& estimate, const NavTable& truth) {
  TrackPairing out;
  if (estimate.has_images && truth.has_images) {
    out.pairs = PairByImage(estimate, truth);
    out.by = "image";
  }
  if (out.pairs.empty() && estimate.has_times && truth.has_times) {
    out.pairs = PairByTime(estimate, truth);
    out.by = "time";
  }
  if (out.pairs.empty()) {
    std::string tried;
    if (estimate.has_images && truth.has_images)
      tried = "no image name is in both (e.g. '" + FirstImage(estimate) + "' here, '" + FirstImage(truth) + "' there)";
    else
      tried = std::string(estimate.has_images ? "the truth has" : "this file has") + " no image names";
    if (estimate.has_times && truth.has_times)
      tried += " and no time_s within " + FormatNumber(TimePairingTolerance(truth)) + " s of a truth time";
    else
      tried += std::string(" and no time_s column in ") + (estimate.has_times ? "the truth" : "this file");
    throw InputError(estimate.source, 0, "image", "no frame in common with " + truth.source + ": " + tried);
  }
  // Truth time order; file order for frames without times.
  const bool timed = std::all_of(out.pairs.begin(), out.pairs.end(),
                                 [&](const FramePair& p) { return truth.records[p.truth].time_s.has_value(); });
  std::stable_sort(out.pairs.begin(), out.pairs.end(), [&](const FramePair& a, const FramePair& b) {
    if (timed) return *truth.records[a.truth].time_s < *truth.records[b.truth].time_s;
    return a.truth < b.truth;
  });
  return out;
}

}  // namespace seamap
