#include "server/server_options.h"

#include <cstdint>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "core/util/error.h"
#include "server/http/origin_policy.h"

namespace seamap::server {
namespace {

// The whole-number settings, their names in the config file and on the
// command line, and their ranges: one table for FromJson and Check.
struct IntSetting {
  const char* key;
  const char* option;
  int ServerOptions::*field;
  int lo, hi;
  const char* what;  // "a port number " or ""
};
constexpr IntSetting kIntSettings[] = {
    {"port", "--port", &ServerOptions::port, 0, 65535, "a port number "},
    {"threads", "--threads", &ServerOptions::threads, 2, 1024, ""},
    {"max_streams", "--max-streams", &ServerOptions::max_streams, 1, 1024, ""},
};

std::string RangeError(const IntSetting& s, int64_t value) {
  return std::string("expected ") + s.what + std::to_string(s.lo) + ".." + std::to_string(s.hi) + ", got " +
         std::to_string(value);
}

}  // namespace

ServerOptions ServerOptions::FromJson(const nlohmann::json& server, const std::string& source) {
  if (!server.is_object()) throw InputError(source, 0, "server", "expected an object, got " + server.dump());
  ServerOptions o;
  for (const auto& [key, value] : server.items()) {
    const std::string field = "server." + key;
    if (key == "host" || key == "token") {
      if (!value.is_string()) throw InputError(source, 0, field, "expected a string, got " + value.dump());
      (key == "host" ? o.host : o.token) = value.get<std::string>();
      if (key == "host" && o.host.empty()) throw InputError(source, 0, field, "expected an address, got \"\"");
      continue;
    }
    if (key == "allow_origins") {
      if (!value.is_array()) throw InputError(source, 0, field, "expected an array of origins, got " + value.dump());
      for (const auto& origin : value) {
        if (!origin.is_string()) throw InputError(source, 0, field, "expected origin strings, got " + origin.dump());
        o.allow_origins.push_back(origin.get<std::string>());
      }
      try {
        OriginPolicy::Check(o.allow_origins);
      } catch (const InputError& e) {
        throw InputError(source, 0, field, e.detail());
      }
      continue;
    }
    const IntSetting* setting = nullptr;
    for (const IntSetting& s : kIntSettings)
      if (key == s.key) setting = &s;
    if (!setting)
      throw InputError(source, 0, field, "unknown key (known: host, port, token, threads, max_streams, allow_origins)");
    if (!value.is_number_integer()) throw InputError(source, 0, field, "expected a whole number, got " + value.dump());
    const int64_t v = value.get<int64_t>();
    if (v < setting->lo || v > setting->hi) throw InputError(source, 0, field, RangeError(*setting, v));
    o.*(setting->field) = static_cast<int>(v);
  }
  return o;
}

void ServerOptions::Check() const {
  if (host.empty()) throw InputError("", 0, "--host", "expected an address, got an empty one");
  for (const IntSetting& s : kIntSettings)
    if (this->*(s.field) < s.lo || this->*(s.field) > s.hi)
      throw InputError("", 0, s.option, RangeError(s, this->*(s.field)));
  OriginPolicy::Check(allow_origins);
  if (!web_dir.empty()) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(std::filesystem::path(web_dir) / "index.html", ec))
      throw InputError(web_dir, 0, "--web", "has no index.html; expected the console's folder (web/ of SeaMap)");
  }
}

}  // namespace seamap::server
