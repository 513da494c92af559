#include "core/detect/score_thresholds.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "core/detect/onnx_meta.h"
#include "core/detect/yolo_model.h"
#include "core/util/error.h"

namespace seamap {

float ScoreThresholds::For(int class_id) const {
  if (class_id >= 0 && static_cast<size_t>(class_id) < per_class.size()) return per_class[class_id];
  return all;
}

float ScoreThresholds::Lowest() const {
  float lowest = all;
  for (float s : per_class) lowest = std::min(lowest, s);
  return lowest;
}

std::vector<float> ParseClassMinScores(const std::string& text, const std::vector<std::string>& names, float fallback,
                                       const std::string& source) {
  const std::string key = "seamap.class_min_scores";
  const auto bad = [&](const std::string& what) {
    return InputError(source, 0, key, what + " (got '" + Excerpt(text) + "')");
  };
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception&) {
    throw bad("expected a JSON object {\"tyre\": 0.6, ...} or a list of scores in class order");
  }
  const auto score = [&](const nlohmann::json& v, const std::string& name) {
    if (!v.is_number()) throw bad("the score of '" + Excerpt(name) + "' is not a number");
    const double s = v.get<double>();
    if (!(s >= kMinScoreFloor && s <= 1)) throw bad("the score of '" + Excerpt(name) + "' is outside 0.001..1");
    return static_cast<float>(s);
  };
  std::vector<float> scores(names.size(), fallback);
  if (j.is_array()) {
    if (j.size() != names.size())
      throw bad("expected " + std::to_string(names.size()) + " scores (one per class), got " +
                std::to_string(j.size()));
    for (size_t i = 0; i < names.size(); ++i) scores[i] = score(j[i], names[i]);
  } else if (j.is_object()) {
    for (const auto& [name, v] : j.items()) {
      const auto it = std::find(names.begin(), names.end(), name);
      if (it == names.end()) throw bad("'" + Excerpt(name) + "' is not one of the model's classes");
      scores[static_cast<size_t>(it - names.begin())] = score(v, name);
    }
  } else {
    throw bad("expected a JSON object {\"tyre\": 0.6, ...} or a list of scores in class order");
  }
  return scores;
}

}  // namespace seamap
