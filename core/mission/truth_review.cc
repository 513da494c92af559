#include "core/mission/truth_review.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <tuple>

#include "core/geo/local_frame.h"
#include "core/util/error.h"

namespace seamap {

std::vector<TruthObject> ReadObjectsTruth(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "", "cannot read the truth (truth/objects.json of seamap simulate --objects)");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path, 0, "", std::string("not JSON: ") + std::string(e.what()).substr(0, 100));
  }
  if (!j.is_object() || !j.contains("objects") || !j["objects"].is_array())
    throw InputError(path, 0, "objects", "expected an \"objects\" array");
  std::vector<TruthObject> out;
  for (size_t i = 0; i < j["objects"].size(); ++i) {
    const auto& o = j["objects"][i];
    const std::string where = "objects[" + std::to_string(i) + "]";
    try {
      TruthObject t;
      t.class_name = o.at("class").get<std::string>();
      t.centre = {o.at("lat").get<double>(), o.at("lon").get<double>()};
      t.size_m = o.at("size_m").get<double>();
      t.west = t.south = 1e300, t.east = t.north = -1e300;
      for (const auto& p : o.at("footprint_lonlat")) {
        const double lon = p.at(0).get<double>(), lat = p.at(1).get<double>();
        t.west = std::min(t.west, lon), t.east = std::max(t.east, lon);
        t.south = std::min(t.south, lat), t.north = std::max(t.north, lat);
      }
      if (!(t.west < t.east && t.south < t.north)) throw std::runtime_error("empty footprint");
      out.push_back(t);
    } catch (const std::exception& e) {
      throw InputError(path, 0, where,
                       std::string("expected class, lat, lon, size_m and footprint_lonlat: ") +
                           std::string(e.what()).substr(0, 100));
    }
  }
  return out;
}

TruthReviewResult ReviewAgainstTruth(DetectionBook& book, const std::vector<TruthObject>& truth,
                                     const TruthReviewOptions& options) {
  TruthReviewResult result;
  std::vector<Detection> found, marks;
  for (const Detection& d : book.Query(DetectionFilter{})) (d.source == "recogniser" ? found : marks).push_back(d);
  // Candidate pairs within reach, nearest first, taken one to one.
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t k = 0; k < truth.size(); ++k) {
    const LocalFrame frame(truth[k].centre);
    const double reach = std::max(options.min_radius_m, options.radius_fraction * truth[k].size_m);
    for (size_t i = 0; i < found.size(); ++i) {
      const LocalXY p = frame.FromLatLon(found[i].position);
      const double d = std::hypot(p.east, p.north);
      if (d <= reach) pairs.emplace_back(d, i, k);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> match_of(found.size(), -1);
  std::vector<bool> truth_seen(truth.size(), false);
  for (const auto& [d, i, k] : pairs)
    if (match_of[i] < 0 && !truth_seen[k]) match_of[i] = static_cast<int>(k), truth_seen[k] = true;
  for (size_t i = 0; i < found.size(); ++i) {
    const int k = match_of[i];
    const bool right = k >= 0 && truth[k].class_name == found[i].class_name;
    if (k >= 0 && !right) truth_seen[k] = false;  // the wrong class: rejected, and the object marked anew
    if (found[i].status == "confirmed" || found[i].status == "rejected") {
      ++result.kept;
      continue;
    }
    book.Update(found[i].id, nlohmann::json{{"status", right ? "confirmed" : "rejected"}, {"note", options.note}});
    ++(right ? result.confirmed : result.rejected);
  }
  for (size_t k = 0; k < truth.size(); ++k) {
    if (truth_seen[k]) continue;
    const TruthObject& t = truth[k];
    // Marked already (a review run before): not twice.
    const LocalFrame frame(t.centre);
    const double reach = std::max(options.min_radius_m, options.radius_fraction * t.size_m);
    if (std::any_of(marks.begin(), marks.end(), [&](const Detection& m) {
          const LocalXY p = frame.FromLatLon(m.position);
          return m.class_name == t.class_name && std::hypot(p.east, p.north) <= reach;
        }))
      continue;
    const nlohmann::json ring = {
        {t.west, t.north}, {t.west, t.south}, {t.east, t.south}, {t.east, t.north}, {t.west, t.north}};
    book.Create({{"type", "Feature"},
                 {"geometry", {{"type", "Point"}, {"coordinates", {t.centre.lon, t.centre.lat}}}},
                 {"properties", {{"class", t.class_name}, {"box", ring}, {"note", options.note}}}});
    ++result.added;
  }
  return result;
}

}  // namespace seamap
