#pragma once
// The score a box must reach to be kept, per class: a fine-tune that learns a
// new class validates its own operating point without moving the old
// classes' (metadata seamap.class_min_scores, written by
// scripts/train_detector.py). Models without it keep one threshold for all.
#include <string>
#include <vector>

namespace seamap {

struct ScoreThresholds {
  float all = 0.4f;               // seamap.min_score or --min-score: classes without their own
  std::vector<float> per_class;   // by class id; empty = `all` for every class
  float For(int class_id) const;  // the threshold of class_id
  float Lowest() const;           // the lowest of all: what a decoder must keep before it knows the class
};

// `seamap.class_min_scores`: a JSON object {"tyre": 0.6, ...} (classes not
// named keep `fallback`) or a list of scores in class order. Each score must
// lie in [kMinScoreFloor, 1]. Throws InputError(source, 0,
// "seamap.class_min_scores", ...) naming the class and quoting the text when
// malformed, a class is unknown or a score out of range.
std::vector<float> ParseClassMinScores(const std::string& text, const std::vector<std::string>& names, float fallback,
                                       const std::string& source);

}  // namespace seamap
