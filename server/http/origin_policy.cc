#include "server/http/origin_policy.h"

#include <algorithm>
#include <cctype>

#include "core/util/error.h"
#include "server/http/http_tokens.h"

namespace seamap::server {
namespace {

std::string Lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

// A host as browsers serialise it: a name or IPv4 address (letters, digits,
// '-', '.', '_'; IDNs are in punycode) or an IPv6 literal in brackets.
bool IsHost(std::string_view host) {
  if (host.empty()) return false;
  if (host.front() == '[')
    return host.size() > 2 && host.back() == ']' && std::all_of(host.begin() + 1, host.end() - 1, [](char c) {
             return std::isxdigit(static_cast<unsigned char>(c)) || c == ':' || c == '.';
           });
  return std::all_of(host.begin(), host.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '_';
  });
}

// The server's own origin as the page that sent the request would have it:
// the Host field under http (or https, behind a TLS proxy that keeps Host).
bool IsOwnOrigin(std::string_view host, const std::string& origin) {
  for (const char* scheme : {"http://", "https://"}) {
    auto own = NormalizeOrigin(scheme + std::string(TrimSpace(host)));
    if (own && *own == origin) return true;
  }
  return false;
}

}  // namespace

std::optional<std::string> NormalizeOrigin(std::string_view origin) {
  const size_t sep = origin.find("://");
  if (sep == std::string_view::npos || sep == 0) return std::nullopt;
  const std::string scheme = Lower(origin.substr(0, sep));
  if (!std::isalpha(static_cast<unsigned char>(scheme[0])) || !std::all_of(scheme.begin(), scheme.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
      }))
    return std::nullopt;
  std::string_view authority = origin.substr(sep + 3);
  // The port follows the last ':' outside an IPv6 literal's brackets.
  const size_t bracket = authority.rfind(']');
  const size_t colon = authority.rfind(':');
  std::string_view host = authority, port;
  if (colon != std::string_view::npos && (bracket == std::string_view::npos || colon > bracket)) {
    host = authority.substr(0, colon);
    port = authority.substr(colon + 1);
    if (port.empty() || port.size() > 5 ||
        !std::all_of(port.begin(), port.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }) ||
        std::stoi(std::string(port)) > 65535)
      return std::nullopt;
    while (port.size() > 1 && port.front() == '0') port.remove_prefix(1);
  }
  if (!IsHost(host)) return std::nullopt;
  std::string out = scheme + "://" + Lower(host);
  const bool default_port = (scheme == "http" && port == "80") || (scheme == "https" && port == "443");
  if (!port.empty() && !default_port) out += ":" + std::string(port);
  return out;
}

OriginPolicy::OriginPolicy(const std::vector<std::string>& allowed) {
  for (const std::string& a : allowed)
    if (auto o = NormalizeOrigin(a)) allowed_.push_back(*o);
}

void OriginPolicy::Check(const std::vector<std::string>& allowed) {
  for (const std::string& a : allowed)
    if (!NormalizeOrigin(a))
      throw InputError(
          "", 0, "--allow-origin",
          "expected an origin: scheme://host[:port] with no path, e.g. http://10.0.0.5:3000, got '" + a + "'");
}

std::optional<std::string> OriginPolicy::RefuseWrite(std::string_view host, std::optional<std::string_view> origin,
                                                     std::optional<std::string_view> sec_fetch_site) const {
  const std::string advice =
      "; a page of another site may not change this mission (start the server with "
      "--allow-origin ORIGIN to let an integration's pages write)";
  if (origin) {
    // Browsers send Origin with every write: it says which page asked.
    const auto normal = NormalizeOrigin(TrimSpace(*origin));
    if (normal && (IsOwnOrigin(host, *normal) || Allowed(*normal))) return std::nullopt;
    return "cross-site write refused: Origin '" + std::string(*origin) + "' is not this server's (http://" +
           std::string(TrimSpace(host)) + ")" + advice;
  }
  // A browser that leaves Origin out still says where the request comes from.
  if (sec_fetch_site && !IEquals(TrimSpace(*sec_fetch_site), "same-origin") &&
      !IEquals(TrimSpace(*sec_fetch_site), "none"))
    return "cross-site write refused: Sec-Fetch-Site is '" + std::string(*sec_fetch_site) + "'" + advice;
  return std::nullopt;  // not a browser's request, or the browser's own user typed it
}

std::optional<std::string> OriginPolicy::Allowed(std::string_view origin) const {
  const auto normal = NormalizeOrigin(TrimSpace(origin));
  if (normal && std::find(allowed_.begin(), allowed_.end(), *normal) != allowed_.end()) return normal;
  return std::nullopt;
}

bool OriginPolicy::IsSafeMethod(std::string_view method) {
  return method == "GET" || method == "HEAD" || method == "OPTIONS";
}

}  // namespace seamap::server
