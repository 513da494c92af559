#include "core/mission/operator_box.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/geo/local_frame.h"
#include "core/mission/detection_error.h"

namespace seamap {
namespace {

constexpr double kAgree_m = 0.01;

std::vector<LatLon> RingOf(double west, double south, double east, double north) {
  return {{north, west}, {south, west}, {south, east}, {north, east}, {north, west}};
}

}  // namespace

void ApplyOperatorBox(const nlohmann::json* box, const nlohmann::json* size_m, Detection* d) {
  if (!box && !size_m) return;
  if ((box && box->is_null() && (!size_m || size_m->is_null())) || (!box && size_m->is_null())) {
    d->box.clear();
    d->size_m.reset();
    return;
  }
  const LocalFrame frame(d->position);  // metres east/north of the mark
  std::optional<std::array<double, 2>> size;
  if (size_m && !size_m->is_null()) {
    if (!size_m->is_array() || size_m->size() != 2 || !(*size_m)[0].is_number() || !(*size_m)[1].is_number())
      throw DetectionError::Invalid("properties.size_m", "expected [east-west, north-south] in metres");
    const double w = (*size_m)[0].get<double>(), h = (*size_m)[1].get<double>();
    if (!(w > 0 && w <= kMaxOperatorBox_m && h > 0 && h <= kMaxOperatorBox_m))
      throw DetectionError::Invalid("properties.size_m", "expected two sizes in (0, 50] metres");
    size = std::array<double, 2>{w, h};
  }
  if (box && !box->is_null()) {
    const char* expected = "expected a closed ring of 5 [lon, lat] points (NW, SW, SE, NE, NW)";
    if (!box->is_array() || box->size() != 5) throw DetectionError::Invalid("properties.box", expected);
    double west = 1e300, east = -1e300, south = 1e300, north = -1e300;
    for (const auto& p : *box) {
      if (!p.is_array() || p.size() < 2 || !p[0].is_number() || !p[1].is_number())
        throw DetectionError::Invalid("properties.box", expected);
      const double lon = p[0].get<double>(), lat = p[1].get<double>();
      if (!(lon >= -180 && lon <= 180 && lat >= -90 && lat <= 90))
        throw DetectionError::Invalid("properties.box", "lon must be in [-180, 180] and lat in [-90, 90]");
      west = std::min(west, lon), east = std::max(east, lon), south = std::min(south, lat),
      north = std::max(north, lat);
    }
    if ((*box)[0] != (*box)[4]) throw DetectionError::Invalid("properties.box", "the ring must be closed (5th = 1st)");
    const LocalXY sw = frame.FromLatLon({south, west}), ne = frame.FromLatLon({north, east});
    const double w = ne.east - sw.east, h = ne.north - sw.north;
    if (!(w > 0.005 && h > 0.005)) throw DetectionError::Invalid("properties.box", "the box has no area");
    if (w > kMaxOperatorBox_m || h > kMaxOperatorBox_m)
      throw DetectionError::Invalid("properties.box", "expected a box of at most 50 m a side");
    if (!(d->position.lon >= west && d->position.lon <= east && d->position.lat >= south && d->position.lat <= north))
      throw DetectionError::Invalid("properties.box", "the mark's point (geometry) must lie inside its box");
    if (size && (std::abs((*size)[0] - w) > kAgree_m || std::abs((*size)[1] - h) > kAgree_m))
      throw DetectionError::Invalid("properties.size_m", "does not agree with properties.box (" + std::to_string(w) +
                                                             " x " + std::to_string(h) + " m); send one of them");
    d->box = RingOf(west, south, east, north);
    d->size_m = std::array<double, 2>{w, h};
    return;
  }
  // size_m alone: a box of that size centred on the mark.
  const LatLon sw = frame.ToLatLon({-(*size)[0] / 2, -(*size)[1] / 2});
  const LatLon ne = frame.ToLatLon({(*size)[0] / 2, (*size)[1] / 2});
  d->box = RingOf(sw.lon, sw.lat, ne.lon, ne.lat);
  d->size_m = size;
}

}  // namespace seamap
