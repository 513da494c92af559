#include "core/enhance/chain_choice.h"

#include "core/util/error.h"

namespace seamap {
namespace {

// A fresh chain for `list`, its flat field seeded once from `seed`.
EnhanceChain SeededChain(const std::string& list, const std::vector<cv::Mat>& seed) {
  EnhanceChain chain = EnhanceChain::FromOpList(list, "--feature-enhance");
  if (chain.SeedFrames() > 0) chain.Seed(seed);
  return chain;
}

}  // namespace

void FeatureEnhanceOptions::Check() const {
  if (spec.empty()) throw InputError("", 0, "--feature-enhance", "expected off, auto or an op list");
  if (spec != "off" && spec != "auto") EnhanceChain::FromOpList(spec, "--feature-enhance");  // throws naming the op
  if (probe_frames < 2) throw InputError("", 0, "--feature-enhance", "auto needs at least two probe frames");
  if (!(min_gain >= 0) || !(enough_inliers > 0))
    throw InputError("", 0, "--feature-enhance", "auto needs a gain >= 0 and an inlier level > 0");
}

EnhancementChoice ChooseEnhancementByInliers(const FeatureEnhanceOptions& options, const std::vector<cv::Mat>& seed,
                                             const MeasureWithChain& measure) {
  options.Check();
  EnhancementChoice choice;
  if (options.spec == "off") return choice;
  if (options.spec != "auto") {
    choice.chain = SeededChain(options.spec, seed);
    return choice;
  }
  if (seed.size() < 2) return choice;
  choice.trials.push_back(measure(EnhanceChain()));
  if (choice.trials.front().inliers >= options.enough_inliers) return choice;
  double best = choice.trials.front().inliers * (1 + options.min_gain);
  for (const std::string& list : options.candidates) {
    choice.trials.push_back(measure(SeededChain(list, seed)));
    if (choice.trials.back().inliers > best) {
      best = choice.trials.back().inliers;
      // A fresh copy for the survey: the probe's images taught the flat
      // field once already (Seed), not twice.
      choice.chain = SeededChain(list, seed);
    }
  }
  return choice;
}

}  // namespace seamap
