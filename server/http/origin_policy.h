#pragma once
// Which browser pages may change the mission. A page on another site can
// make the operator's browser send a form-style POST (no preflight, no
// token needed when the server has none): such writes are refused from the
// browser's own Origin and Sec-Fetch-Site fields. The server's own pages,
// the origins an operator allows (--allow-origin) and clients that are not
// browsers (curl, scripts: they send neither field) keep writing. The same
// allowed origins get CORS answers, so an integration's page can read and write.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace seamap::server {

// "Scheme://Host[:port]" as a browser serialises it (RFC 6454): lower case,
// the scheme's default port dropped; nullopt when `origin` is not one (a
// path, user info, an empty or malformed host or port, "null").
std::optional<std::string> NormalizeOrigin(std::string_view origin);

class OriginPolicy {
 public:
  // `allowed`: origins as given to --allow-origin; Check() them first
  // (an entry that does not normalise is ignored here).
  explicit OriginPolicy(const std::vector<std::string>& allowed = {});

  // Throws InputError naming --allow-origin and the expected form for the
  // first entry that is not an origin.
  static void Check(const std::vector<std::string>& allowed);

  // Is a write (any method but GET, HEAD, OPTIONS) with these header fields
  // allowed? nullopt: yes; otherwise why not, for a 403. `host` is the
  // request's Host field (the server's own origin is http or https on it);
  // a field the request lacks is nullopt.
  std::optional<std::string> RefuseWrite(std::string_view host, std::optional<std::string_view> origin,
                                         std::optional<std::string_view> sec_fetch_site) const;

  // The normalised origin when `origin` is one of the allowed ones (for the
  // CORS answer), else nullopt.
  std::optional<std::string> Allowed(std::string_view origin) const;

  // True for the methods that change nothing.
  static bool IsSafeMethod(std::string_view method);

 private:
  std::vector<std::string> allowed_;  // normalised
};

}  // namespace seamap::server
