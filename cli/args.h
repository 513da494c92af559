#pragma once
// Minimal command-line parsing shared by the subcommands: `--name value`,
// `--name=value`, boolean `--flag`, and positionals. Unknown or malformed
// options raise InputError naming the option and what was expected.
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace seamap::cli {

class Args {
 public:
  // flags: names of options that take no value (e.g. "quiet").
  Args(int argc, char** argv, int first, std::set<std::string> flags = {});

  std::optional<std::string> Get(const std::string& name);
  // Every value of an option given more than once (`--allow-origin A --allow-origin B`).
  std::vector<std::string> GetAll(const std::string& name);
  std::string Require(const std::string& name);
  std::string GetOr(const std::string& name, const std::string& fallback);
  double GetDouble(const std::string& name, double fallback);
  int GetInt(const std::string& name, int fallback);
  bool Flag(const std::string& name);
  // Gives an option a value unless the command line set it.
  void SetDefault(const std::string& name, const std::string& value) { values_.emplace(name, value); }
  const std::vector<std::string>& positionals() const { return positionals_; }

  // Throws InputError for any option that no Get/Flag call asked for.
  void RejectUnknown() const;

 private:
  std::map<std::string, std::string> values_;  // the last value of each option
  std::map<std::string, std::vector<std::string>> all_values_;
  std::set<std::string> flags_set_;
  std::set<std::string> known_flags_;
  std::set<std::string> used_;
  std::vector<std::string> positionals_;
};

// Parses "lat,lon" (degrees). Throws InputError(param, ...) when malformed or out of range.
struct LatLonArg {
  double lat, lon;
};
LatLonArg ParseLatLon(const std::string& text, const std::string& param);

// --seed N (default 1) of the simulators. Throws InputError naming --seed when negative.
uint64_t SeedArg(Args& args);

}  // namespace seamap::cli
