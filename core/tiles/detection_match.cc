#include "core/tiles/detection_match.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/tiles/mission_classes.h"
#include "core/util/utc_time.h"

namespace seamap {
namespace {

double SmallerSideM(const Detection& d) {
  return d.size_m ? std::min((*d.size_m)[0], (*d.size_m)[1]) : 0;
}

}  // namespace

std::string ModelFile(const std::string& model) {
  return model.substr(0, model.find('#'));
}

double GroundDistanceM(const LatLon& a, const LatLon& b) {
  constexpr double kMetresPerDegree = 6378137.0 * M_PI / 180;
  const double north = (a.lat - b.lat) * kMetresPerDegree;
  const double east = (a.lon - b.lon) * kMetresPerDegree * std::cos((a.lat + b.lat) / 2 * M_PI / 180);
  return std::hypot(north, east);
}

bool SameObject(const Detection& earlier, const Detection& found) {
  if (earlier.source == "operator" || earlier.class_name != found.class_name ||
      ModelFile(earlier.model) != ModelFile(found.model))
    return false;
  const double radius = std::max(0.10, std::min(SmallerSideM(earlier), SmallerSideM(found)) / 4);
  return GroundDistanceM(earlier.position, found.position) <= radius;
}

std::vector<int> MatchEarlier(const std::vector<Detection>& earlier, const std::vector<Detection>& found) {
  std::vector<std::tuple<double, int, int>> pairs;  // distance, found, earlier
  for (size_t f = 0; f < found.size(); ++f)
    for (size_t e = 0; e < earlier.size(); ++e)
      if (SameObject(earlier[e], found[f]))
        pairs.emplace_back(GroundDistanceM(earlier[e].position, found[f].position), static_cast<int>(f),
                           static_cast<int>(e));
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> match(found.size(), -1);
  std::vector<bool> taken(earlier.size(), false);
  for (const auto& [distance, f, e] : pairs) {
    if (match[f] >= 0 || taken[e]) continue;
    match[f] = e;
    taken[e] = true;
  }
  return match;
}

std::vector<Detection> StoreFound(TileStore& store, std::vector<Detection> found, const std::string& source,
                                  const std::string& model, const std::vector<std::string>& class_names) {
  std::vector<std::string> table = MissionClassTable(store);
  if (ExtendClassTable(&table, class_names)) StoreClassTable(&store, table);
  StoreMissionT0(&store);
  int64_t last_id = 0, last_seq = 0;
  std::vector<Detection> old;
  for (const Detection& d : store.Detections()) {
    last_id = std::max(last_id, d.id);
    last_seq = std::max(last_seq, d.seq);
    if (d.source == source && ModelFile(d.model) == ModelFile(model)) old.push_back(d);
  }
  const std::vector<int> continues = MatchEarlier(old, found);
  std::vector<bool> used(old.size(), false);
  const std::string now = UtcNowIso8601();
  std::vector<Detection> stored;
  for (size_t k = 0; k < found.size(); ++k) {
    Detection& d = found[k];
    const int match = continues[k];
    if (match >= 0) {
      used[match] = true;
      // The operator's review stays, and a rejected object is not recreated: it is kept as rejected.
      d.id = old[match].id;
      d.created = old[match].created;
      d.note = old[match].note;
      if (!old[match].status.empty()) d.status = old[match].status;
    } else {
      d.id = ++last_id;
      d.created = now;
    }
    d.updated = now;
    d.seq = ++last_seq;
    store.PutDetection(d);
    stored.push_back(d);
  }
  // Gone from this search: dropped, unless the operator reviewed it (kept as they left it).
  for (size_t i = 0; i < old.size(); ++i)
    if (!used[i] && old[i].status != "confirmed" && old[i].status != "rejected") store.DeleteDetection(old[i].id);
  return stored;
}

}  // namespace seamap
