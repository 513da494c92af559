#include "core/tiles/mission_records.h"

#include <cmath>

namespace seamap {

bool IsDetectionSource(const std::string& source) {
  return source == "recogniser" || source == "operator" || source == "stereo";
}

bool IsFiniteDetection(const Detection& d) {
  const auto finite = [](double v) { return std::isfinite(v); };
  const auto finite_pair = [&](const std::optional<std::array<double, 2>>& p) {
    return !p || (finite((*p)[0]) && finite((*p)[1]));
  };
  if (!finite(d.score) || !finite(d.position.lat) || !finite(d.position.lon)) return false;
  for (const LatLon& c : d.box)
    if (!finite(c.lat) || !finite(c.lon)) return false;
  return finite_pair(d.position_m) && finite_pair(d.size_m);
}

std::vector<Detection> MissionRecords::ReadableDetections(std::vector<int64_t>* unreadable) const {
  std::vector<Detection> out;
  for (Detection& d : Detections()) {
    if (IsFiniteDetection(d))
      out.push_back(std::move(d));
    else if (unreadable)
      unreadable->push_back(d.id);
  }
  return out;
}

bool IsDetectionStatus(const std::string& status) {
  return status == "unconfirmed" || status == "confirmed" || status == "rejected";
}

void NormaliseDetection(Detection* d) {
  if (!IsDetectionSource(d->source)) {
    if (d->model.empty()) d->model = d->source;
    d->source = "recogniser";
  }
  if (!IsDetectionStatus(d->status)) d->status = d->source == "operator" ? "confirmed" : "unconfirmed";
}

}  // namespace seamap
