#pragma once
// An ordered list of enhancement operations applied to every frame, parsed from
// an op list ("flatfield,brightness,clahe:clip_limit=3") or from the build
// config ({"ops": [{"op": "clahe", "clip_limit": 2.0, "tile_grid": 8}, ...]}).
// Copies share state (the flat-field estimate).
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/enhance/enhance_op.h"

namespace seamap {

class EnhanceChain {
 public:
  EnhanceChain() = default;  // identity

  // json: {"ops": [...]}, each entry {"op": name, <param>: value...}. source names the
  // file for errors. Unknown op/param or bad value -> InputError(source, 0, "<op>.<param>").
  static EnhanceChain FromJson(const nlohmann::json& config, const std::string& source);
  // "op[:param=value[:param=value]],op..."; "none" or "" = identity, "default" = Default().
  static EnhanceChain FromOpList(const std::string& list, const std::string& source);
  // The chain the enhance-report evidence favours (see docs_enhance.md).
  static EnhanceChain Default();

  // Thread-safe. Rejects unsupported image types with InputError naming the op.
  cv::Mat Apply(const cv::Mat& frame) const;

  // One line, e.g. "flatfield(max_gain=4, ...) -> clahe(clip_limit=2, tile_grid=8)".
  std::string Describe() const;
  // Op-list form, parameters only where they differ from the defaults, e.g.
  // "flatfield,clahe:clip_limit=3" (or "none"); FromOpList(Names()) rebuilds the chain.
  std::string Names() const;
  nlohmann::json ToJson() const;

  bool empty() const { return ops_.empty(); }
  const std::vector<std::shared_ptr<EnhanceOp>>& ops() const { return ops_; }

  // How many frames a caller should pass to Seed before the first Apply (0 = none needed).
  int SeedFrames() const;
  // Shows sample frames to stateful ops (the flat-field estimate), each seeing the
  // frame as processed by the ops before it.
  void Seed(const std::vector<cv::Mat>& frames) const;

 private:
  std::vector<std::shared_ptr<EnhanceOp>> ops_;
};

}  // namespace seamap
