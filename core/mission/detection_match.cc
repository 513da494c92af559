#include "core/mission/detection_match.h"

#include <algorithm>
#include <cmath>
#include <tuple>

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
  if (earlier.source == "operator" || earlier.source != found.source || earlier.class_name != found.class_name ||
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

}  // namespace seamap
