#pragma once
// One named step of an enhancement chain with its parameters, e.g.
// {"op": "clahe", "clip_limit": 2.0, "tile_grid": 8}.
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

namespace seamap {

class EnhanceOp {
 public:
  virtual ~EnhanceOp() = default;
  virtual std::string name() const = 0;
  // Every parameter with its current value (defaults included).
  virtual nlohmann::json params() const = 0;
  // Thread-safe; input and output share type and size.
  virtual cv::Mat Apply(const cv::Mat& image) const = 0;
  // Frames a caller should show Observe before the first Apply (flat field); 0 = none.
  virtual int seed_frames() const { return 0; }
  virtual void Observe(const cv::Mat& /*image*/) const {}
};

// Names accepted by MakeEnhanceOp, in the recommended chain order.
const std::vector<std::string>& EnhanceOpNames();

// Builds op `name`; params is a JSON object of parameter overrides (may be null).
// Unknown op or parameter, wrong type or out-of-range value ->
// InputError(source, 0, "<op>.<param>", what was expected).
std::shared_ptr<EnhanceOp> MakeEnhanceOp(const std::string& name, const nlohmann::json& params,
                                         const std::string& source);

}  // namespace seamap
