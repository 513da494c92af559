#include "server/http/request_head.h"

#include <algorithm>
#include <cctype>
#include <utility>

#include "server/http/http_tokens.h"

namespace seamap::server {
namespace {

using Kind = RequestHead::Kind;

RequestHead Verdict(Kind kind) {
  RequestHead h;
  h.kind = kind;
  return h;
}

RequestHead Refuse(const char* error, int status = 400) {
  RequestHead h;
  h.kind = Kind::kRefuse;
  h.status = status;
  h.error = error;
  return h;
}

// Field values: visible characters, space, tab and obs-text; no other controls.
bool IsValueChar(unsigned char c) {
  return c == '\t' || (c >= 0x20 && c != 0x7f);
}

// The characters of a tile path the front end decodes itself; escapes and
// anything else are the backend's to decode or refuse.
bool IsTilePathChar(unsigned char c) {
  return std::isalnum(c) || c == '/' || c == '.' || c == '-' || c == '_' || c == '~';
}

bool HasDotSegment(std::string_view path) {
  while (!path.empty()) {
    const size_t slash = std::min(path.find('/'), path.size());
    const std::string_view segment = path.substr(0, slash);
    if (segment == "." || segment == "..") return true;
    path.remove_prefix(std::min(slash + 1, path.size()));
  }
  return false;
}

// "HTTP/" DIGIT "." DIGIT
bool IsVersion(std::string_view v) {
  return v.size() == 8 && v.substr(0, 5) == "HTTP/" && std::isdigit(static_cast<unsigned char>(v[5])) && v[6] == '.' &&
         std::isdigit(static_cast<unsigned char>(v[7]));
}

// A catalogue mission's tile target ("/missions/{id}/tiles/..."): the id, and
// the target from "/tiles/" on. Ids are [a-z0-9_-]+ (core/mission/map_catalog).
std::optional<std::pair<std::string_view, std::string_view>> MissionTileTarget(std::string_view target) {
  constexpr std::string_view kMissions = "/missions/";
  if (target.substr(0, kMissions.size()) != kMissions) return std::nullopt;
  const size_t end = target.find('/', kMissions.size());
  if (end == std::string_view::npos || end == kMissions.size()) return std::nullopt;
  const std::string_view id = target.substr(kMissions.size(), end - kMissions.size());
  if (!std::all_of(id.begin(), id.end(),
                   [](unsigned char c) { return (c >= 'a' && c <= 'z') || std::isdigit(c) || c == '_' || c == '-'; }))
    return std::nullopt;
  return std::make_pair(id, target.substr(end));
}

// A plain tile target ("/tiles/z/x/y.ext[?query]"): its path after "/tiles/".
std::optional<std::string_view> TilePath(std::string_view target) {
  constexpr std::string_view kPrefix = "/tiles/", kJson = ".json";
  if (target.substr(0, kPrefix.size()) != kPrefix || target.find('#') != std::string_view::npos) return std::nullopt;
  const std::string_view path = target.substr(kPrefix.size(), target.find('?') - kPrefix.size());
  if (!std::all_of(path.begin(), path.end(), [](unsigned char c) { return IsTilePathChar(c); })) return std::nullopt;
  if (HasDotSegment(path)) return std::nullopt;
  if (path.size() >= kJson.size() && path.substr(path.size() - kJson.size()) == kJson) return std::nullopt;  // TileJSON
  return path;
}

}  // namespace

RequestHead ParseRequestHead(std::string_view bytes, const RequestHeadLimits& limits) {
  const size_t head_end = std::min(bytes.size(), limits.max_head_bytes);
  const size_t max_line = std::min(limits.max_line_bytes, limits.max_head_bytes);
  const size_t line_end = std::min(head_end, max_line);
  // Out of bytes before a line ended: wait, unless a limit is what stopped us.
  auto ran_out = [&](size_t limit) {
    if (bytes.size() < limit) return Verdict(Kind::kNeedMore);
    return limit == max_line ? Refuse("the request line is too long", 414) : Refuse("the header is too long", 431);
  };

  // The request line: method SP target SP version CRLF, visible ASCII.
  size_t pos = 0;
  for (;; ++pos) {
    if (pos >= line_end) return ran_out(max_line);
    const unsigned char c = bytes[pos];
    if (c == '\r' || c == '\n') break;
    if (c < 0x20 || c == 0x7f) return Refuse("a control character in the request line");
    if (c > 0x7f) return Refuse("a non-ASCII byte in the request line");
  }
  if (bytes[pos] == '\n') return Refuse("a line ends with LF, not CRLF");
  if (pos + 1 >= line_end) return ran_out(max_line);
  if (bytes[pos + 1] != '\n') return Refuse("a CR without LF in the request line");
  if (pos == 0) return Refuse("an empty line before the request line");
  const std::string_view line = bytes.substr(0, pos);
  const size_t s1 = line.find(' ');
  const size_t s2 = s1 == std::string_view::npos ? s1 : line.find(' ', s1 + 1);
  if (s2 == std::string_view::npos || line.find(' ', s2 + 1) != std::string_view::npos || s1 == 0 || s2 == s1 + 1)
    return Refuse("expected 'METHOD TARGET HTTP/1.1' as the request line");
  const std::string_view method = line.substr(0, s1), target = line.substr(s1 + 1, s2 - s1 - 1),
                         version = line.substr(s2 + 1);
  if (!std::all_of(method.begin(), method.end(), [](unsigned char c) { return IsTokenChar(c); }))
    return Refuse("the method is not a token");
  if (!IsVersion(version)) return Refuse("expected HTTP/1.1 or HTTP/1.0 as the version");
  if (version[5] != '1') return Refuse("only HTTP/1.x is served here", 505);
  pos += 2;

  // Header fields "name: value" up to the blank line.
  RequestHead head;
  std::optional<size_t> content_length;
  bool close = false, keep_alive = false, to_backend = false;
  int transfer_encodings = 0;  // fields; only one "chunked" is served
  while (true) {
    if (pos >= head_end) return ran_out(limits.max_head_bytes);
    if (bytes[pos] == '\r' || bytes[pos] == '\n') {
      if (bytes[pos] == '\n') return Refuse("a line ends with LF, not CRLF");
      if (pos + 1 >= head_end) return ran_out(limits.max_head_bytes);
      if (bytes[pos + 1] != '\n') return Refuse("a CR without LF in the header");
      head.size = pos + 2;
      break;
    }
    if (bytes[pos] == ' ' || bytes[pos] == '\t') return Refuse("a folded header field (obs-fold)");
    const size_t name_start = pos;
    while (pos < head_end && IsTokenChar(static_cast<unsigned char>(bytes[pos]))) ++pos;
    if (pos >= head_end) return ran_out(limits.max_head_bytes);
    if (bytes[pos] != ':' || pos == name_start) return Refuse("expected 'Name: value' as a header field");
    const std::string_view name = bytes.substr(name_start, pos - name_start);
    const size_t value_start = ++pos;
    while (pos < head_end && IsValueChar(static_cast<unsigned char>(bytes[pos]))) ++pos;
    if (pos >= head_end) return ran_out(limits.max_head_bytes);
    if (bytes[pos] == '\n') return Refuse("a line ends with LF, not CRLF");
    if (bytes[pos] != '\r') return Refuse("a control character in a header field");
    if (pos + 1 >= head_end) return ran_out(limits.max_head_bytes);
    if (bytes[pos + 1] != '\n') return Refuse("a CR without LF in the header");
    const std::string_view value = TrimSpace(bytes.substr(value_start, pos - value_start));
    pos += 2;

    if (IEquals(name, "content-length")) {
      if (value.empty() || value.size() > 15 || value.find_first_not_of("0123456789") != std::string_view::npos)
        return Refuse("Content-Length is not a number");
      const size_t length = std::stoull(std::string(value));
      if (content_length && *content_length != length) return Refuse("two Content-Lengths");
      content_length = length;
    } else if (IEquals(name, "transfer-encoding")) {
      // httplib reads a body as chunked only for exactly this value, and to
      // the close for any other: the front end would lose the request's end.
      if (!IEquals(value, "chunked") || ++transfer_encodings > 1)
        return Refuse("only 'Transfer-Encoding: chunked' is served", 501);
      head.chunked = true;
    } else if (IEquals(name, "expect") || IEquals(name, "upgrade")) {
      to_backend = true;  // 100-continue, another protocol: the backend's business
    } else if (IEquals(name, "if-none-match")) {
      head.if_none_match = head.if_none_match ? *head.if_none_match + ", " + std::string(value) : std::string(value);
    } else if (IEquals(name, "connection")) {
      close = close || HasToken(value, "close");
      keep_alive = keep_alive || HasToken(value, "keep-alive");
    }
  }
  // Where a request ends must be the same for httplib: it reads a body only
  // for these methods, and one without a length up to the close.
  const bool takes_body = method == "POST" || method == "PUT" || method == "PATCH" || method == "DELETE";
  head.http_1_0 = version == "HTTP/1.0";  // HTTP/1.2 and later are taken as 1.1
  if (head.chunked) {
    // Both lengths is how requests are smuggled past a proxy (RFC 9112 6.3).
    if (content_length) return Refuse("both Transfer-Encoding and Content-Length");
    if (head.http_1_0) return Refuse("Transfer-Encoding in an HTTP/1.0 request");
    if (!takes_body) return Refuse("a body on a request that takes none");
  }
  if (!takes_body && content_length.value_or(0) > 0) return Refuse("a body on a request that takes none");
  if (takes_body && method != "DELETE" && !content_length && !head.chunked)
    return Refuse("a body needs a Content-Length", 411);
  head.keep_alive = !close && (!head.http_1_0 || keep_alive);
  head.head_only = method == "HEAD";
  const auto mission = MissionTileTarget(target);
  const std::optional<std::string_view> tile = TilePath(mission ? mission->second : target);
  if (tile && (method == "GET" || method == "HEAD") && !to_backend) {
    head.kind = Kind::kTile;
    head.tile_path = std::string(*tile);
    if (mission) head.mission_id = std::string(mission->first);
  } else {
    head.kind = Kind::kBackend;
    head.body_bytes = content_length.value_or(0);  // 0 with chunked: the chunks say
    head.if_none_match.reset();
  }
  return head;
}

}  // namespace seamap::server
