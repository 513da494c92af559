#include "core/enhance/enhance_op.h"

#include <cmath>
#include <functional>
#include <map>
#include <set>

#include "core/enhance/brightness_recovery.h"
#include "core/enhance/clahe.h"
#include "core/enhance/color_balance.h"
#include "core/enhance/dehaze.h"
#include "core/enhance/flat_field.h"
#include "core/enhance/gamma.h"
#include "core/util/error.h"

namespace seamap {
namespace {
using nlohmann::json;

// Reads typed parameters from an op's JSON object and rejects any it was not asked for.
class ParamReader {
 public:
  ParamReader(std::string op, const json& params, std::string source)
      : op_(std::move(op)), params_(params), source_(std::move(source)) {
    if (!params_.is_null() && !params_.is_object())
      throw InputError(source_, 0, op_, "expected an object of parameters, got " + params_.dump());
  }

  void Read(const std::string& key, double& value) {
    if (const json* v = Find(key)) {
      if (!v->is_number()) Fail(key, "a number", *v);
      value = v->get<double>();
    }
    out_[key] = value;
  }
  void Read(const std::string& key, int& value) {
    if (const json* v = Find(key)) {
      if (!v->is_number() || v->get<double>() != std::floor(v->get<double>())) Fail(key, "a whole number", *v);
      value = v->get<int>();
    }
    out_[key] = value;
  }
  void Read(const std::string& key, bool& value) {
    if (const json* v = Find(key)) {
      if (!v->is_boolean()) Fail(key, "true or false", *v);
      value = v->get<bool>();
    }
    out_[key] = value;
  }

  // Call after all Reads and before Validate; returns every parameter with its value.
  json Finish() const {
    if (params_.is_object())
      for (const auto& [key, value] : params_.items())
        if (key != "op" && key != "comment" && key.rfind('_', 0) != 0 && !out_.contains(key)) {
          std::string known;
          for (const auto& [k, v] : out_.items()) known += (known.empty() ? "" : ", ") + k;
          throw InputError(source_, 0, op_ + "." + key, "unknown parameter of '" + op_ + "' (known: " + known + ")");
        }
    return out_;
  }

  // Runs a params Validate(), re-raising its error with this chain's source.
  template <typename P>
  void Validate(const P& p) const {
    try {
      p.Validate();
    } catch (const InputError& e) {
      throw InputError(source_, 0, e.field(), e.detail());
    }
  }

 private:
  const json* Find(const std::string& key) const {
    if (!params_.is_object()) return nullptr;
    auto it = params_.find(key);
    return it == params_.end() ? nullptr : &*it;
  }
  [[noreturn]] void Fail(const std::string& key, const std::string& expected, const json& got) const {
    throw InputError(source_, 0, op_ + "." + key, "expected " + expected + ", got " + got.dump());
  }

  std::string op_;
  const json& params_;
  std::string source_;
  json out_ = json::object();
};

// A stateless op: a function of the image and its parameter struct.
template <typename P>
class FunctionOp : public EnhanceOp {
 public:
  FunctionOp(std::string name, P params, json described, std::function<cv::Mat(const cv::Mat&, const P&)> fn)
      : name_(std::move(name)), params_(params), described_(std::move(described)), fn_(std::move(fn)) {}
  std::string name() const override { return name_; }
  json params() const override { return described_; }
  cv::Mat Apply(const cv::Mat& image) const override { return fn_(image, params_); }

 private:
  std::string name_;
  P params_;
  json described_;
  std::function<cv::Mat(const cv::Mat&, const P&)> fn_;
};

class FlatFieldOp : public EnhanceOp {
 public:
  FlatFieldOp(const FlatFieldParams& params, json described)
      : flat_(std::make_shared<FlatField>(params)), described_(std::move(described)) {}
  std::string name() const override { return "flatfield"; }
  json params() const override { return described_; }
  cv::Mat Apply(const cv::Mat& image) const override { return flat_->Apply(image); }
  int seed_frames() const override { return flat_->params().seed_frames; }
  void Observe(const cv::Mat& image) const override { flat_->Add(image); }

 private:
  std::shared_ptr<FlatField> flat_;  // the running estimate; guarded by its own mutex
  json described_;
};

template <typename P>
std::shared_ptr<EnhanceOp> MakeFunctionOp(const std::string& name, ParamReader& reader, const P& p,
                                          cv::Mat (*fn)(const cv::Mat&, const P&)) {
  json described = reader.Finish();
  reader.Validate(p);
  return std::make_shared<FunctionOp<P>>(name, p, std::move(described), fn);
}

cv::Mat DehazeFn(const cv::Mat& image, const DehazeParams& p) {
  return Dehaze(image, p);
}

}  // namespace

const std::vector<std::string>& EnhanceOpNames() {
  static const std::vector<std::string> names = {"flatfield", "colorbalance", "dehaze", "brightness", "clahe", "gamma"};
  return names;
}

std::shared_ptr<EnhanceOp> MakeEnhanceOp(const std::string& name, const json& params, const std::string& source) {
  ParamReader r(name, params, source);
  if (name == "gamma") {
    GammaParams p;
    r.Read("gamma", p.gamma);
    return MakeFunctionOp(name, r, p, &ApplyGamma);
  }
  if (name == "clahe") {
    ClaheParams p;
    r.Read("clip_limit", p.clip_limit);
    r.Read("tile_grid", p.tile_grid);
    return MakeFunctionOp(name, r, p, &ApplyClahe);
  }
  if (name == "brightness") {
    BrightnessParams p;
    r.Read("window", p.window);
    r.Read("max_gain", p.max_gain);
    r.Read("noise_floor", p.noise_floor);
    r.Read("percentile", p.percentile);
    r.Read("min_mean_fraction", p.min_mean_fraction);
    r.Read("strength", p.strength);
    return MakeFunctionOp(name, r, p, &RecoverBrightness);
  }
  if (name == "dehaze") {
    DehazeParams p;
    r.Read("window", p.window);
    r.Read("omega", p.omega);
    r.Read("t0", p.t0);
    r.Read("airlight_fraction", p.airlight_fraction);
    r.Read("gate", p.gate);
    r.Read("blur_threshold", p.blur_threshold);
    r.Read("blur_levels", p.blur_levels);
    r.Read("guided_radius", p.guided_radius);
    r.Read("guided_eps", p.guided_eps);
    return MakeFunctionOp(name, r, p, &DehazeFn);
  }
  if (name == "colorbalance") {
    ColorBalanceParams p;
    r.Read("linear", p.linear);
    r.Read("max_gain", p.max_gain);
    r.Read("clip", p.clip);
    return MakeFunctionOp(name, r, p, &BalanceColor);
  }
  if (name == "flatfield") {
    FlatFieldParams p;
    r.Read("smooth", p.smooth);
    r.Read("max_gain", p.max_gain);
    r.Read("memory", p.memory);
    r.Read("learn", p.learn);
    r.Read("seed_frames", p.seed_frames);
    json described = r.Finish();
    r.Validate(p);
    return std::make_shared<FlatFieldOp>(p, std::move(described));
  }
  std::string known;
  for (const auto& n : EnhanceOpNames()) known += (known.empty() ? "" : ", ") + n;
  throw InputError(source, 0, name.empty() ? "op" : name, "unknown enhancement operation (known: " + known + ")");
}

}  // namespace seamap
