#include "core/mission/detection_filter.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <vector>

#include "core/mission/detection_error.h"

namespace seamap {
namespace {

double ParseNumber(const std::string& text, const std::string& name) {
  try {
    size_t used = 0;
    double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw DetectionError::Invalid(name, "expected a number, got '" + text + "'");
}

std::vector<std::string> SplitList(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, ','))
    if (!part.empty()) out.push_back(part);
  return out;
}

}  // namespace

DetectionFilter ParseDetectionFilter(const std::optional<std::string>& bbox, const std::optional<std::string>& classes,
                                     const std::optional<std::string>& min_score,
                                     const std::optional<std::string>& since, const std::optional<std::string>& status,
                                     const std::optional<std::string>& source) {
  DetectionFilter f;
  if (bbox) {
    std::vector<double> v;
    std::stringstream in(*bbox);
    std::string part;
    while (std::getline(in, part, ',')) v.push_back(ParseNumber(part, "bbox"));
    if (v.size() != 4 || v[0] > v[2] || v[1] > v[3])
      throw DetectionError::Invalid("bbox", "expected west,south,east,north with west <= east and south <= north");
    f.bbox = LatLonBounds{v[0], v[1], v[2], v[3]};
  }
  if (classes)
    for (const std::string& v : SplitList(*classes)) f.classes.insert(v);
  if (min_score) f.min_score = ParseNumber(*min_score, "min_score");
  if (since) {
    const double v = ParseNumber(*since, "since");
    if (v < 0 || v != std::floor(v)) throw DetectionError::Invalid("since", "expected a change number >= 0");
    // Past the largest seq (2^63 - 1) no change is newer: nothing. A plain
    // cast is undefined there (1e19 became INT64_MIN: everything again).
    f.since = v >= 9223372036854775808.0 ? std::numeric_limits<int64_t>::max() : static_cast<int64_t>(v);
  }
  if (status)
    for (const std::string& v : SplitList(*status)) {
      if (!IsDetectionStatus(v))
        throw DetectionError::Invalid("status", "'" + v + "' is not unconfirmed, confirmed or rejected");
      f.statuses.insert(v);
    }
  if (source)
    for (const std::string& v : SplitList(*source)) {
      if (!IsDetectionSource(v))
        throw DetectionError::Invalid("source", "'" + v + "' is not recogniser, operator or stereo");
      f.sources.insert(v);
    }
  return f;
}

bool Passes(const DetectionFilter& f, const Detection& d) {
  if (f.bbox && (d.position.lon < f.bbox->west || d.position.lon > f.bbox->east || d.position.lat < f.bbox->south ||
                 d.position.lat > f.bbox->north))
    return false;
  if (!f.classes.empty() && !f.classes.count(d.class_name)) return false;
  if (f.min_score && d.score < *f.min_score) return false;
  if (f.since && d.seq <= *f.since) return false;
  if (!f.statuses.empty() && !f.statuses.count(d.status)) return false;
  if (!f.sources.empty() && !f.sources.count(d.source)) return false;
  return true;
}

}  // namespace seamap
