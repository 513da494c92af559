#pragma once
// Small pieces of HTTP/1.1 syntax (RFC 9110) shared by the front end's
// request and response parsers.
#include <string_view>

namespace seamap::server {

// A token character: field names, methods, Connection options.
bool IsTokenChar(unsigned char c);
// Is `a` equal to `lower` (all lower case) ignoring case?
bool IEquals(std::string_view a, std::string_view lower);
// Without leading and trailing spaces and tabs.
std::string_view TrimSpace(std::string_view s);
// Does a comma-separated field value list `token` (`token` in lower case)?
bool HasToken(std::string_view list, std::string_view token);

}  // namespace seamap::server
