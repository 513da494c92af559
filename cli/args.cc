#include "cli/args.h"

#include <cmath>
#include <cstdlib>

#include "core/util/error.h"

namespace seamap::cli {
namespace {
double ParseNumber(const std::string& text, const std::string& param) {
  char* end = nullptr;
  double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw InputError("", 0, "--" + param, "expected a number, got '" + text + "'");
  return v;
}
}  // namespace

Args::Args(int argc, char** argv, int first, std::set<std::string> flags) : known_flags_(std::move(flags)) {
  for (int i = first; i < argc; ++i) {
    std::string a = argv[i];
    if (a.size() > 2 && a.compare(0, 2, "--") == 0) {
      std::string name = a.substr(2);
      auto eq = name.find('=');
      if (eq != std::string::npos) {
        values_[name.substr(0, eq)] = name.substr(eq + 1);
        all_values_[name.substr(0, eq)].push_back(name.substr(eq + 1));
      } else if (known_flags_.count(name)) {
        flags_set_.insert(name);
      } else if (i + 1 < argc) {
        values_[name] = argv[++i];
        all_values_[name].push_back(argv[i]);
      } else {
        throw InputError("", 0, "--" + name, "expected a value after it");
      }
    } else {
      positionals_.push_back(a);
    }
  }
}

std::optional<std::string> Args::Get(const std::string& name) {
  used_.insert(name);
  auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

std::vector<std::string> Args::GetAll(const std::string& name) {
  used_.insert(name);
  auto it = all_values_.find(name);
  return it == all_values_.end() ? std::vector<std::string>{} : it->second;
}

std::string Args::Require(const std::string& name) {
  auto v = Get(name);
  if (!v) throw InputError("", 0, "--" + name, "is required");
  return *v;
}

std::string Args::GetOr(const std::string& name, const std::string& fallback) {
  auto v = Get(name);
  return v ? *v : fallback;
}

double Args::GetDouble(const std::string& name, double fallback) {
  auto v = Get(name);
  return v ? ParseNumber(*v, name) : fallback;
}

int Args::GetInt(const std::string& name, int fallback) {
  auto v = Get(name);
  if (!v) return fallback;
  double d = ParseNumber(*v, name);
  if (d != std::floor(d)) throw InputError("", 0, "--" + name, "expected a whole number, got '" + *v + "'");
  return static_cast<int>(d);
}

bool Args::Flag(const std::string& name) {
  used_.insert(name);
  return flags_set_.count(name) > 0;
}

void Args::RejectUnknown() const {
  for (const auto& [name, value] : values_)
    if (!used_.count(name)) throw InputError("", 0, "--" + name, "unknown option");
  for (const auto& name : flags_set_)
    if (!used_.count(name)) throw InputError("", 0, "--" + name, "unknown option");
}

LatLonArg ParseLatLon(const std::string& text, const std::string& param) {
  auto comma = text.find(',');
  if (comma == std::string::npos) throw InputError("", 0, param, "expected 'lat,lon' in degrees, got '" + text + "'");
  LatLonArg r{ParseNumber(text.substr(0, comma), param.substr(2)),
              ParseNumber(text.substr(comma + 1), param.substr(2))};
  if (std::fabs(r.lat) > 90 || std::fabs(r.lon) > 180)
    throw InputError("", 0, param,
                     "latitude must be within [-90, 90] and longitude within [-180, 180], got '" + text + "'");
  return r;
}

uint64_t SeedArg(Args& args) {
  const int seed = args.GetInt("seed", 1);
  if (seed < 0) throw InputError("", 0, "--seed", "expected a non-negative whole number");
  return static_cast<uint64_t>(seed);
}

}  // namespace seamap::cli
