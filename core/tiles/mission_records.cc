#include "core/tiles/mission_records.h"

namespace seamap {

bool IsDetectionSource(const std::string& source) {
  return source == "recogniser" || source == "operator" || source == "stereo";
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
