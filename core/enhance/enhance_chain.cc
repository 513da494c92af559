#include "core/enhance/enhance_chain.h"

#include <algorithm>
#include <sstream>

#include "core/util/error.h"

namespace seamap {
namespace {
using nlohmann::json;

std::string Trim(const std::string& s) {
  size_t b = s.find_first_not_of(" \t");
  size_t e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

std::vector<std::string> Split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::stringstream in(s);
  for (std::string part; std::getline(in, part, sep);) parts.push_back(Trim(part));
  return parts;
}

std::string FormatValue(const json& v) {
  if (v.is_number_float()) {
    std::ostringstream out;
    out << v.get<double>();
    return out.str();
  }
  return v.dump();
}
}  // namespace

EnhanceChain EnhanceChain::FromJson(const json& config, const std::string& source) {
  if (!config.is_object())
    throw InputError(source, 0, "", "expected an object like {\"ops\": [...]}, got " + config.dump());
  for (const auto& [key, value] : config.items())
    if (key != "ops" && key != "comment" && key.rfind('_', 0) != 0)  // "_..." and "comment" are notes
      throw InputError(source, 0, key, "unknown key of the enhancement config (expected only \"ops\")");
  auto it = config.find("ops");
  if (it == config.end() || !it->is_array())
    throw InputError(source, 0, "ops", "expected an array of operations like [{\"op\": \"clahe\"}]");
  EnhanceChain chain;
  for (size_t i = 0; i < it->size(); ++i) {
    const json& entry = (*it)[i];
    const std::string where = "ops[" + std::to_string(i) + "]";
    if (!entry.is_object() || !entry.contains("op") || !entry["op"].is_string())
      throw InputError(source, 0, where, "expected an object with a string \"op\", got " + entry.dump());
    chain.ops_.push_back(MakeEnhanceOp(entry["op"].get<std::string>(), entry, source));
  }
  return chain;
}

EnhanceChain EnhanceChain::FromOpList(const std::string& list, const std::string& source) {
  const std::string text = Trim(list);
  if (text.empty() || text == "none") return {};
  if (text == "default") return Default();
  EnhanceChain chain;
  for (const std::string& token : Split(text, ',')) {
    std::vector<std::string> parts = Split(token, ':');
    if (parts.empty() || parts[0].empty())
      throw InputError(source, 0, "", "empty operation in '" + list + "' (expected e.g. \"flatfield,clahe\")");
    json params = json::object();
    for (size_t i = 1; i < parts.size(); ++i) {
      auto eq = parts[i].find('=');
      if (eq == std::string::npos || eq == 0)
        throw InputError(source, 0, parts[0], "expected 'param=value' after ':', got '" + parts[i] + "'");
      std::string key = parts[i].substr(0, eq), value = parts[i].substr(eq + 1);
      // Numbers and true/false parse as JSON; anything else is kept as a string and rejected by type.
      json parsed = json::parse(value, nullptr, false);
      params[key] = parsed.is_discarded() ? json(value) : parsed;
    }
    chain.ops_.push_back(MakeEnhanceOp(parts[0], params, source));
  }
  return chain;
}

// Chosen from enhance-report runs on degraded synthetic surveys (docs_enhance.md):
// dehazing always (the blur gate skipped clear frames that dehazing still helped),
// then CLAHE with clip 3; the flat field first so the lamp does not bias the airlight.
EnhanceChain EnhanceChain::Default() {
  return FromOpList("flatfield,dehaze:gate=false,clahe:clip_limit=3", "default chain");
}

cv::Mat EnhanceChain::Apply(const cv::Mat& frame) const {
  if (ops_.empty()) return frame.clone();
  cv::Mat image = frame;
  for (const auto& op : ops_) image = op->Apply(image);
  return image;
}

std::string EnhanceChain::Describe() const {
  if (ops_.empty()) return "none";
  std::string out;
  for (const auto& op : ops_) {
    if (!out.empty()) out += " -> ";
    out += op->name() + "(";
    bool first = true;
    const json params = op->params();  // keep alive: items() only references it
    for (const auto& [key, value] : params.items()) {
      out += (first ? "" : ", ") + key + "=" + FormatValue(value);
      first = false;
    }
    out += ")";
  }
  return out;
}

std::string EnhanceChain::Names() const {
  if (ops_.empty()) return "none";
  std::string out;
  for (const auto& op : ops_) {
    out += (out.empty() ? "" : ",") + op->name();
    // Only parameters that differ from the op's defaults, so the text stays short.
    const json defaults = MakeEnhanceOp(op->name(), json(), "defaults")->params();
    const json params = op->params();
    for (const auto& [key, value] : params.items())
      if (defaults.value(key, json()) != value) out += ":" + key + "=" + FormatValue(value);
  }
  return out;
}

json EnhanceChain::ToJson() const {
  json ops = json::array();
  for (const auto& op : ops_) {
    json entry = {{"op", op->name()}};
    entry.update(op->params());
    ops.push_back(entry);
  }
  return {{"ops", ops}};
}

int EnhanceChain::SeedFrames() const {
  int n = 0;
  for (const auto& op : ops_) n = std::max(n, op->seed_frames());
  return n;
}

void EnhanceChain::Seed(const std::vector<cv::Mat>& frames) const {
  // Only ops up to the last one that wants seeding need to run.
  size_t last = 0;
  for (size_t i = 0; i < ops_.size(); ++i)
    if (ops_[i]->seed_frames() > 0) last = i + 1;
  for (const cv::Mat& frame : frames) {
    cv::Mat image = frame;
    for (size_t i = 0; i < last; ++i) {
      ops_[i]->Observe(image);
      if (i + 1 < last) image = ops_[i]->Apply(image);
    }
  }
}

}  // namespace seamap
