// ParseRequestHead: what the tile front end answers itself, what it waits
// for, what it relays to the backend, and what it refuses.
#include "server/http/request_head.h"

#include <gtest/gtest.h>

#include <vector>

namespace seamap::server {
namespace {

using Kind = RequestHead::Kind;

const std::string kTileGet = "GET /tiles/3/4/2.png HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";

std::string KindName(Kind k) {
  switch (k) {
    case Kind::kNeedMore:
      return "need more";
    case Kind::kTile:
      return "tile";
    case Kind::kBackend:
      return "backend";
    case Kind::kRefuse:
      return "refuse";
  }
  return "?";
}

// The request `line` with `fields` ("Name: value\r\n" each) and the blank line.
std::string Request(const std::string& line, const std::string& fields = "Host: x\r\n") {
  return line + "\r\n" + fields + "\r\n";
}

void ExpectKind(const std::string& bytes, Kind kind, const std::string& why = "",
                const RequestHeadLimits& limits = {}) {
  EXPECT_EQ(KindName(ParseRequestHead(bytes, limits).kind), KindName(kind)) << "'" << bytes << "' " << why;
}

TEST(RequestHead, APlainTileGet) {
  const RequestHead h = ParseRequestHead(kTileGet);
  ASSERT_EQ(h.kind, Kind::kTile);
  EXPECT_EQ(h.size, kTileGet.size());
  EXPECT_EQ(h.tile_path, "3/4/2.png");
  EXPECT_FALSE(h.head_only);
  EXPECT_TRUE(h.keep_alive);
  EXPECT_FALSE(h.http_1_0);
  EXPECT_FALSE(h.if_none_match);

  const RequestHead head = ParseRequestHead(Request("HEAD /tiles/enhanced/3/4/2.png HTTP/1.1"));
  ASSERT_EQ(head.kind, Kind::kTile);
  EXPECT_TRUE(head.head_only);
  EXPECT_EQ(head.tile_path, "enhanced/3/4/2.png");
  EXPECT_EQ(ParseRequestHead("GET /tiles/3/4/2.png HTTP/1.1\r\n\r\n").kind, Kind::kTile) << "no fields at all";
}

// A catalogue's tiles ("/missions/{id}/tiles/...") are answered by the front end too.
TEST(RequestHead, ACatalogueMissionsTileGet) {
  const RequestHead h = ParseRequestHead(Request("GET /missions/dive_a-2/tiles/raw/3/4/2.png?v=1 HTTP/1.1"));
  ASSERT_EQ(h.kind, Kind::kTile);
  EXPECT_EQ(h.mission_id, "dive_a-2");
  EXPECT_EQ(h.tile_path, "raw/3/4/2.png");
  EXPECT_EQ(ParseRequestHead(kTileGet).mission_id, "");
  ExpectKind(Request("GET /missions//tiles/3/4/2.png HTTP/1.1"), Kind::kBackend, "no id");
  ExpectKind(Request("GET /missions/Dive/tiles/3/4/2.png HTTP/1.1"), Kind::kBackend, "not a catalogue id");
  ExpectKind(Request("GET /missions/d%61/tiles/3/4/2.png HTTP/1.1"), Kind::kBackend, "an escape");
  ExpectKind(Request("GET /missions/dive/tiles.json HTTP/1.1"), Kind::kBackend, "TileJSON");
  ExpectKind(Request("GET /missions/dive/tiles/raw.json HTTP/1.1"), Kind::kBackend, "a layer's TileJSON");
  ExpectKind(Request("GET /missions/dive/api/status HTTP/1.1"), Kind::kBackend, "the API");
  ExpectKind(Request("GET /missions/dive/tiles/../../x HTTP/1.1"), Kind::kBackend, "dot segments");
}

TEST(RequestHead, EveryPrefixOfARequestWaitsForMore) {
  for (size_t n = 0; n < kTileGet.size(); ++n) ExpectKind(kTileGet.substr(0, n), Kind::kNeedMore);
}

TEST(RequestHead, PipelinedRequestsAreTakenOneAtATime) {
  const std::string second = Request("HEAD /tiles/3/4/3.png HTTP/1.1");
  const std::string post = "POST /api/detections HTTP/1.1\r\nContent-Length: 2\r\n\r\n";
  std::string bytes = kTileGet + second + post + "{}" + kTileGet;
  RequestHead h = ParseRequestHead(bytes);
  ASSERT_EQ(h.kind, Kind::kTile);
  ASSERT_EQ(h.size, kTileGet.size());
  bytes.erase(0, h.size);
  h = ParseRequestHead(bytes);
  ASSERT_EQ(h.kind, Kind::kTile);
  EXPECT_EQ(h.tile_path, "3/4/3.png");
  EXPECT_TRUE(h.head_only);
  bytes.erase(0, h.size);
  h = ParseRequestHead(bytes);
  ASSERT_EQ(h.kind, Kind::kBackend);
  EXPECT_EQ(h.size, post.size());
  EXPECT_EQ(h.body_bytes, 2u);
  bytes.erase(0, h.size + h.body_bytes);
  EXPECT_EQ(ParseRequestHead(bytes).kind, Kind::kTile);
}

TEST(RequestHead, OtherRequestsGoToTheBackendWithTheirLength) {
  for (const std::string line :
       {"GET /api/status HTTP/1.1", "GET / HTTP/1.1", "GET /tiles.json HTTP/1.1", "GET /tiles/enhanced.json HTTP/1.1",
        "DELETE /tiles/3/4/2.png HTTP/1.1", "TRACE /tiles/3/4/2.png HTTP/1.1", "OPTIONS * HTTP/1.1",
        "get /tiles/3/4/2.png HTTP/1.1", "GET /TILES/3/4/2.png HTTP/1.1", "GET http://x/tiles/3/4/2.png HTTP/1.1",
        "GET /tiles HTTP/1.1", "GET /tilesx/3/4/2.png HTTP/1.1", "HEAD /api/status HTTP/1.0"}) {
    const RequestHead h = ParseRequestHead(Request(line));
    EXPECT_EQ(KindName(h.kind), "backend") << line;
    EXPECT_EQ(h.size, Request(line).size()) << line;
    EXPECT_EQ(h.body_bytes, 0u) << line;
  }
  const RequestHead head = ParseRequestHead(Request("HEAD /api/status HTTP/1.0"));
  EXPECT_TRUE(head.head_only) << "its answer has no body";
  EXPECT_FALSE(head.keep_alive) << "its answer ends the connection";
  ExpectKind("POST /api/detections HTTP/1.1\r\nContent-Le", Kind::kNeedMore, "the whole head first");
  ExpectKind("\r\nGET /tiles/3/4/2.png HTTP/1.1\r\n\r\n", Kind::kRefuse, "the caller skips empty lines");
  ExpectKind("\r", Kind::kNeedMore, "maybe an empty line: the caller's to skip");
}

TEST(RequestHead, MalformedRequestLinesAreRefused) {
  for (const std::string line :
       {"GET  /tiles/3/4/2.png HTTP/1.1", "GET /tiles/3/4/2.png  HTTP/1.1", "GET /tiles/3/4/2.png HTTP/1.1 ",
        " GET /tiles/3/4/2.png HTTP/1.1", "GET /tiles/3/4/2.png", "GET /tiles/3/4/2.png HTTP/1.1 extra",
        "GET\t/tiles/3/4/2.png HTTP/1.1", "GET /tiles/3/4/2.png\tHTTP/1.1", "GET /tiles/3/4/ 2.png HTTP/1.1",
        "G(T /tiles/3/4/2.png HTTP/1.1", "FOO"})
    ExpectKind(Request(line), Kind::kRefuse, line);
  // A lone CR, a control or non-ASCII byte: refused at once, not waited for.
  ExpectKind("GET /tiles/3/4/2.png HTTP/1.1\rX", Kind::kRefuse);
  ExpectKind(std::string("GET /tiles/3/4/\0", 16), Kind::kRefuse);
  ExpectKind("GET /tiles/3/4/\x7f", Kind::kRefuse);
  ExpectKind("\x01\x02", Kind::kRefuse);
  ExpectKind("GET /tiles/3/4/\xc3\xa9.png", Kind::kRefuse);
  // A bare LF ends a line for lenient servers; RFC 9112 lets a server refuse it.
  ExpectKind("GET /tiles/3/4/2.png HTTP/1.1\n", Kind::kRefuse);
  EXPECT_STRNE(ParseRequestHead(Request("GET  /x HTTP/1.1")).error, "") << "the 400 says what is wrong";
}

TEST(RequestHead, OnlyHttp1IsServed) {
  for (const std::string version : {"HTTP/2.0", "HTTP/0.9", "HTTP/3.1"}) {
    const RequestHead h = ParseRequestHead(Request("GET /tiles/3/4/2.png " + version));
    EXPECT_EQ(KindName(h.kind), "refuse") << version;
    EXPECT_EQ(h.status, 505) << version;
  }
  for (const std::string version :
       {"http/1.1", "HTTP/1.10", "HTTP/1", "HTTP/11", "HTTP/1.1x", "HTTPS/1.1", "HTTP/ 1.1"}) {
    const RequestHead h = ParseRequestHead(Request("GET /tiles/3/4/2.png " + version));
    EXPECT_EQ(KindName(h.kind), "refuse") << version;
    EXPECT_EQ(h.status, 400) << version;
  }
  ExpectKind(Request("GET /tiles/3/4/2.png HTTP/1.0"), Kind::kTile);
  const RequestHead later = ParseRequestHead(Request("GET /tiles/3/4/2.png HTTP/1.2"));
  EXPECT_EQ(later.kind, Kind::kTile);
  EXPECT_TRUE(later.keep_alive) << "a later HTTP/1.x is taken as 1.1";
}

TEST(RequestHead, TheLineAndTheHeadHaveLimits) {
  const RequestHeadLimits limits{64, 128};
  const std::string prefix = "GET /tiles/3/4/2.png?v=";
  const std::string suffix = " HTTP/1.1";
  const std::string fill(64 - 2 - prefix.size() - suffix.size(), 'a');  // the line is exactly 64 bytes with CRLF
  ExpectKind(prefix + fill + suffix + "\r\n\r\n", Kind::kTile, "", limits);
  ExpectKind(prefix + fill + "a" + suffix + "\r\n\r\n", Kind::kRefuse, "", limits);
  EXPECT_EQ(ParseRequestHead(prefix + fill + "a" + suffix + "\r\n\r\n", limits).status, 414);
  ExpectKind(prefix + fill + "a" + suffix + "\r", Kind::kRefuse, "64 bytes and no end yet", limits);
  ExpectKind(prefix + fill + suffix + "\r", Kind::kNeedMore, "63 bytes: not too long yet", limits);

  const std::string line = "GET /tiles/3/4/2.png HTTP/1.1\r\n";
  const std::string field = "X: " + std::string(128 - line.size() - 2 - 5, 'b') + "\r\n";  // the head is 128 bytes
  ExpectKind(line + field + "\r\n", Kind::kTile, "", limits);
  ExpectKind(line + "Y" + field + "\r\n", Kind::kRefuse, "", limits);
  EXPECT_EQ(ParseRequestHead(line + "Y" + field + "\r\n", limits).status, 431);
  ExpectKind(line + "YY" + field, Kind::kRefuse, "128 bytes and no blank line", limits);
  ExpectKind(line + field + "\r", Kind::kNeedMore, "127 bytes", limits);

  // The defaults: an 8 KiB line (httplib's own limit), a 16 KiB head.
  ExpectKind(Request("GET /tiles/3/4/2.png HTTP/1.1", "X-Big: " + std::string(16400, 'c') + "\r\n"), Kind::kRefuse);
  ExpectKind("GET /tiles/3/4/2.png HTTP/1.1\r\nX-Big: " + std::string(16400, 'c'), Kind::kRefuse);
  ExpectKind("GET /tiles/" + std::string(8200, '1'), Kind::kRefuse);
  ExpectKind(Request("GET /api/status?q=" + std::string(8000, 'q') + " HTTP/1.1"), Kind::kBackend);
}

TEST(RequestHead, MalformedHeaderFieldsAreRefused) {
  const std::string line = "GET /tiles/3/4/2.png HTTP/1.1";
  for (const std::string fields : {
           "Host: x\r\n continued\r\n",  // obs-fold
           "Host: x\r\n\tcontinued\r\n",
           "Host x\r\n",         // no colon
           "Host : x\r\n",       // space before the colon
           ": x\r\n",            // no name
           "Ho(st: x\r\n",       // not a token
           "Host: x\rY: z\r\n",  // a lone CR
           "Content-Length: abc\r\n",
           "Content-Length: 0, 0\r\n",
           "Content-Length: -1\r\n",
           "Content-Length: 1\r\nContent-Length: 2\r\n",
       })
    ExpectKind(Request(line, fields), Kind::kRefuse, fields);
  ExpectKind(Request(line, std::string("X: a\0b\r\n", 8)), Kind::kRefuse, "NUL in a value");
  ExpectKind(Request(line, std::string("X\0: ab\r\n", 8)), Kind::kRefuse, "NUL in a name");
  ExpectKind(Request(line, "X: a\x01\r\n"), Kind::kRefuse);
  ExpectKind(Request(line, "Host: x\ny: z\r\n"), Kind::kRefuse, "a bare LF");
  ExpectKind("GET /tiles/3/4/2.png HTTP/1.1\r\nHost: x\r\n\n", Kind::kRefuse, "a bare LF at the end");
  ExpectKind(Request(line, "X: caf\xc3\xa9\r\n"), Kind::kTile, "obs-text in a value is allowed");
  ExpectKind(Request(line, "X:\r\n"), Kind::kTile, "an empty value");
}

TEST(RequestHead, BodiesAreFramedAsHttplibFramesThem) {
  const std::string line = "GET /tiles/3/4/2.png HTTP/1.1";
  ExpectKind(Request(line, "Content-Length: 0\r\n"), Kind::kTile);
  ExpectKind(Request(line, "content-length:  0 \r\n"), Kind::kTile);
  ExpectKind(Request(line, "Content-Length: 0\r\nContent-Length: 0\r\n"), Kind::kTile);
  for (const std::string method : {"POST", "PUT", "PATCH", "DELETE"}) {
    const RequestHead h = ParseRequestHead(Request(method + " /api/detections/1 HTTP/1.1", "Content-Length: 5\r\n"));
    EXPECT_EQ(KindName(h.kind), "backend") << method;
    EXPECT_EQ(h.body_bytes, 5u) << method;
  }
  ExpectKind(Request("DELETE /api/detections/1 HTTP/1.1"), Kind::kBackend, "DELETE needs no length");
  // httplib reads no body for these (the body would be read as the next request)...
  for (const std::string method : {"GET", "HEAD", "OPTIONS"}) {
    const RequestHead h = ParseRequestHead(Request(method + " /api/status HTTP/1.1", "Content-Length: 5\r\n"));
    EXPECT_EQ(KindName(h.kind), "refuse") << method;
    EXPECT_EQ(h.status, 400) << method;
  }
  // ... and reads a POST without a length up to the close.
  const RequestHead post = ParseRequestHead(Request("POST /api/detections HTTP/1.1"));
  EXPECT_EQ(KindName(post.kind), "refuse");
  EXPECT_EQ(post.status, 411);
  for (const std::string fields : {"Expect: 100-continue\r\n", "Upgrade: websocket\r\nConnection: upgrade\r\n"})
    ExpectKind(Request(line, fields), Kind::kBackend, fields);
}

// A chunked body is framed by the front end (ChunkedRequestBody); only what
// httplib reads the same way gets through.
TEST(RequestHead, OnlyAPlainChunkedBodyIsFollowed) {
  for (const std::string fields : {"Transfer-Encoding: chunked\r\n", "TRANSFER-ENCODING:  Chunked \r\n"}) {
    for (const std::string method : {"POST", "PUT", "PATCH", "DELETE"}) {
      const RequestHead h = ParseRequestHead(Request(method + " /api/detections HTTP/1.1", fields));
      EXPECT_EQ(KindName(h.kind), "backend") << method << " " << fields;
      EXPECT_TRUE(h.chunked) << method << " " << fields;
      EXPECT_EQ(h.body_bytes, 0u);
    }
  }
  struct Case {
    std::string line, fields;
    int status;
  };
  const std::vector<Case> refused = {
      {"POST / HTTP/1.1", "Transfer-Encoding: identity\r\n", 501},
      {"POST / HTTP/1.1", "Transfer-Encoding: gzip, chunked\r\n", 501},
      {"POST / HTTP/1.1", "Transfer-Encoding: chunked, chunked\r\n", 501},
      {"POST / HTTP/1.1", "Transfer-Encoding: chunked\r\nTransfer-Encoding: chunked\r\n", 501},
      {"POST / HTTP/1.1", "Transfer-Encoding: %63hunked\r\n", 501},  // httplib would decode it
      {"POST / HTTP/1.1", "Transfer-Encoding: chunked\r\nContent-Length: 5\r\n", 400},
      {"POST / HTTP/1.1", "Content-Length: 5\r\nTransfer-Encoding: chunked\r\n", 400},
      {"POST / HTTP/1.0", "Transfer-Encoding: chunked\r\n", 400},
      {"GET /api/status HTTP/1.1", "Transfer-Encoding: chunked\r\n", 400},
      {"GET /tiles/3/4/2.png HTTP/1.1", "Transfer-Encoding: chunked\r\n", 400},
      {"OPTIONS /api/status HTTP/1.1", "Transfer-Encoding: chunked\r\n", 400},
  };
  for (const Case& c : refused) {
    const RequestHead h = ParseRequestHead(Request(c.line, c.fields));
    EXPECT_EQ(KindName(h.kind), "refuse") << c.line << " " << c.fields;
    EXPECT_EQ(h.status, c.status) << c.line << " " << c.fields << ": " << h.error;
  }
}

TEST(RequestHead, DotSegmentsEscapesAndOddCharactersAreTheBackendsToJudge) {
  for (const std::string target :
       {"/tiles/../etc/passwd", "/tiles/./3/4/2.png", "/tiles/3/4/..", "/tiles/3/../4/2.png", "/tiles/3/4/.",
        "/tiles/3/4/%32.png", "/tiles/%2e%2e/x", "/tiles/3/4/2.png#x", "/tiles/3/4/2+.png", "/tiles/3/4/2.png;x",
        "/tiles/3/4\\2.png", "/tiles/3/4/2.png?a#b"})
    ExpectKind(Request("GET " + target + " HTTP/1.1"), Kind::kBackend, target);
  // Not dot segments: left to the tile path's own checks.
  EXPECT_EQ(ParseRequestHead(Request("GET /tiles/3/4/2..png HTTP/1.1")).tile_path, "3/4/2..png");
  EXPECT_EQ(ParseRequestHead(Request("GET /tiles/.x/3/4/2.png HTTP/1.1")).tile_path, ".x/3/4/2.png");
}

TEST(RequestHead, TheQueryIsDropped) {
  for (const std::string query : {"?v=0123abcd", "?", "?a=%20&b=/../", "?x=1?y=2"}) {
    const RequestHead h = ParseRequestHead(Request("GET /tiles/3/4/2.png" + query + " HTTP/1.1"));
    ASSERT_EQ(h.kind, Kind::kTile) << query;
    EXPECT_EQ(h.tile_path, "3/4/2.png") << query;
  }
}

TEST(RequestHead, HeaderNamesAreCaseInsensitive) {
  RequestHead h = ParseRequestHead(Request("GET /tiles/3/4/2.png HTTP/1.1", "if-NONE-match:  \"abc\" \r\n"));
  ASSERT_EQ(h.kind, Kind::kTile);
  EXPECT_EQ(h.if_none_match, "\"abc\"");
  h = ParseRequestHead(
      Request("GET /tiles/3/4/2.png HTTP/1.1", "If-None-Match: \"a\"\r\nX: y\r\nIF-NONE-MATCH: W/\"b\"\r\n"));
  EXPECT_EQ(h.if_none_match, "\"a\", W/\"b\"") << "repeated fields make one list";
  h = ParseRequestHead(Request("GET /tiles/3/4/2.png HTTP/1.1", "CONNECTION: Close\r\n"));
  EXPECT_FALSE(h.keep_alive);
}

TEST(RequestHead, ConnectionTokensFor10And11) {
  struct Case {
    std::string version, connection;
    bool keep_alive;
  };
  for (const Case& c : std::vector<Case>{{"HTTP/1.1", "", true},
                                         {"HTTP/1.1", "close", false},
                                         {"HTTP/1.1", "keep-alive", true},
                                         {"HTTP/1.1", "keep-alive, close", false},
                                         {"HTTP/1.1", "TE, Close", false},
                                         {"HTTP/1.1", "closed", true},
                                         {"HTTP/1.1", "x-close", true},
                                         {"HTTP/1.0", "", false},
                                         {"HTTP/1.0", "keep-alive", true},
                                         {"HTTP/1.0", " Keep-Alive ", true},
                                         {"HTTP/1.0", "keep-alive, close", false},
                                         {"HTTP/1.0", "keep-alives", false}}) {
    const std::string fields = c.connection.empty() ? "" : "Connection:" + c.connection + "\r\n";
    const RequestHead h = ParseRequestHead(Request("GET /tiles/3/4/2.png " + c.version, fields));
    ASSERT_EQ(h.kind, Kind::kTile) << c.version << " " << c.connection;
    EXPECT_EQ(h.keep_alive, c.keep_alive) << c.version << " '" << c.connection << "'";
    EXPECT_EQ(h.http_1_0, c.version == "HTTP/1.0");
  }
  // Two Connection fields count as one list.
  EXPECT_FALSE(
      ParseRequestHead(Request("GET /tiles/3/4/2.png HTTP/1.1", "Connection: keep-alive\r\nConnection: close\r\n"))
          .keep_alive);
}

}  // namespace
}  // namespace seamap::server
