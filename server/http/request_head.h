#pragma once
// What the tile front end (tile_front_end.*) needs to know of the bytes a
// client sent: is there a whole request head yet; is it a plain tile GET/HEAD
// it answers itself, a request for the backend whose length it knows, or
// something it leaves entirely to the backend; or is it malformed?
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace seamap::server {

struct RequestHeadLimits {
  size_t max_line_bytes = 8192;   // the request line, CRLF included (httplib's own limit)
  size_t max_head_bytes = 16384;  // request line, header fields and the blank line
};

struct RequestHead {
  enum class Kind {
    kNeedMore,  // no verdict yet: wait for more bytes
    kTile,      // a plain tile GET/HEAD: answer it here
    kBackend,   // a well-formed request for the backend: `size` + `body_bytes` long,
                // or `size` and a chunked body (`chunked`: ChunkedRequestBody frames it)
    kRefuse,    // not HTTP/1.x (RFC 9112): answer `status` and close
  };
  Kind kind = Kind::kNeedMore;
  size_t size = 0;                           // kTile, kBackend: the head, blank line included
  size_t body_bytes = 0;                     // kBackend: Content-Length
  bool chunked = false;                      // kBackend: "Transfer-Encoding: chunked"
  bool head_only = false;                    // HEAD: the answer has no body
  bool keep_alive = true;                    // else the connection closes after the answer
  bool http_1_0 = false;                     // a kept connection must then be announced ("Connection: keep-alive")
  std::string tile_path;                     // kTile: after "/tiles/", no query: "z/x/y.ext" or "layer/z/x/y.ext"
  std::string mission_id;                    // kTile of "/missions/{id}/tiles/...": the catalogue's mission
  std::optional<std::string> if_none_match;  // kTile; several fields are joined with ", "
  int status = 400;                          // kRefuse: 400; 411 a body without a length; 414, 431 over the limits;
                                             // 501 a transfer coding other than chunked; 505 not HTTP/1.x
  const char* error = "";                    // kRefuse: what is wrong
};

// Looks at the start of what a client sent (it may hold several pipelined
// requests, or part of one). A head longer than the limits is refused as
// soon as the bytes show it, so the caller never buffers more than
// limits.max_head_bytes. Escapes, dot segments and anything unusual in a
// /tiles/ target make it a kBackend request: the backend decodes or refuses
// it. Lines must end with CRLF (a bare LF is refused, as RFC 9112 allows);
// the empty lines RFC 9112 lets a client send between requests are the
// caller's to skip.
RequestHead ParseRequestHead(std::string_view bytes, const RequestHeadLimits& limits = {});

}  // namespace seamap::server
