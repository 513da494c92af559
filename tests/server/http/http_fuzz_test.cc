// Randomised tests of every parser the server owns (tiles paths, request
// heads, chunked bodies, httplib's answers, HTTP tokens, origins, UTF-8), then
// of a real server on loopback: valid inputs mutated and random bytes, for a
// few seconds each (fuzz.h). No crash, no hang, no answer that is not HTTP,
// and each parser's verdict does not depend on how its bytes arrive.
#include <nlohmann/json.hpp>

#include "server/api_error.h"
#include "server/http/chunked_request.h"
#include "server/http/http_tokens.h"
#include "server/http/origin_policy.h"
#include "server/http/request_head.h"
#include "server/http/response_framer.h"
#include "server/http/utf8.h"
#include "server/tile_path.h"
#include "tests/server/http/fuzz.h"
#include "tests/server/http_test_fixture.h"
#include "tests/server/raw_http.h"

namespace seamap::server {
namespace {

using fuzz::Fuzzer;

// Any bytes, printable in a failure message.
std::string Show(std::string_view bytes) {
  return nlohmann::json(std::string(bytes)).dump(-1, ' ', true, nlohmann::json::error_handler_t::replace);
}

std::string Hex(size_t n, bool upper) {
  char out[24];
  std::snprintf(out, sizeof out, upper ? "%zX" : "%zx", n);
  return out;
}

TEST(Fuzz, TilePaths) {
  const std::vector<std::string> seeds = {"3/4/2.png", "enhanced/3/4/2.png", "30/1073741823/0.jpg", "0/0/0.webp",
                                          "12/2047/1365.png"};
  Fuzzer fz;
  while (fz.Next()) {
    const std::string path = fz.OneIn(4) ? fz.Bytes(40) : fz.Mutate(fz.Pick(seeds));
    try {
      const TilePath t = ParseTilePath(path);
      ASSERT_LE(t.id.z, 30) << fz.Where();
      ASSERT_GE(t.id.x, 0);
      ASSERT_GE(t.id.y, 0);
      ASSERT_LT(t.id.x, int64_t{1} << t.id.z) << fz.Where();
      ASSERT_LT(t.id.y, int64_t{1} << t.id.z) << fz.Where();
      // What was understood, written out again, is understood the same way.
      const std::string again = (t.layer.empty() ? "" : t.layer + "/") + std::to_string(t.id.z) + "/" +
                                std::to_string(t.id.x) + "/" + std::to_string(t.id.y) + "." + t.ext;
      const TilePath u = ParseTilePath(again);
      ASSERT_TRUE(u.layer == t.layer && u.ext == t.ext && u.id.z == t.id.z && u.id.x == t.id.x && u.id.y == t.id.y)
          << fz.Where() << ": " << Show(path) << " vs " << Show(again);
    } catch (const ApiError& e) {
      ASSERT_EQ(e.status(), 400) << fz.Where();
      ASSERT_EQ(std::string(e.what()).rfind("tile path: ", 0), 0u) << fz.Where() << ": " << e.what();
    }
  }
}

std::string KindName(RequestHead::Kind k) {
  return k == RequestHead::Kind::kNeedMore  ? "need more"
         : k == RequestHead::Kind::kTile    ? "tile"
         : k == RequestHead::Kind::kBackend ? "backend"
                                            : "refuse";
}

TEST(Fuzz, RequestHeads) {
  const std::vector<std::string> seeds = {
      "GET /tiles/3/4/2.png HTTP/1.1\r\nHost: 127.0.0.1\r\nIf-None-Match: \"ab\"\r\n\r\n",
      "HEAD /tiles/enhanced/3/4/2.png HTTP/1.0\r\nConnection: keep-alive\r\n\r\n",
      "GET /api/status HTTP/1.1\r\nHost: x\r\nAccept: */*\r\n\r\n",
      "POST /api/detections HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: 2\r\n\r\n{}",
      "POST /api/detections HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n2\r\n{}\r\n0\r\n\r\n",
      "DELETE /api/detections/3 HTTP/1.1\r\nHost: x\r\nOrigin: http://x\r\n\r\n",
      "GET /tiles/3/4/2.png HTTP/1.1\r\n\r\nGET /tiles/3/4/3.png HTTP/1.1\r\n\r\n"};
  Fuzzer fz;
  while (fz.Next()) {
    const std::string bytes = fz.OneIn(5) ? fz.Bytes(300) : fz.Mutate(fz.Pick(seeds));
    RequestHeadLimits limits;
    if (fz.OneIn(3)) limits = {1 + fz.Below(80), 1 + fz.Below(200)};
    const RequestHead h = ParseRequestHead(bytes, limits);
    switch (h.kind) {
      case RequestHead::Kind::kNeedMore:
        ASSERT_LT(bytes.size(), limits.max_head_bytes) << fz.Where() << ": waits past the limit";
        break;
      case RequestHead::Kind::kTile:
      case RequestHead::Kind::kBackend:
        ASSERT_GT(h.size, 0u) << fz.Where();
        ASSERT_LE(h.size, std::min(bytes.size(), limits.max_head_bytes)) << fz.Where();
        ASSERT_EQ(bytes.substr(h.size - 4, 4), "\r\n\r\n") << fz.Where();
        if (h.kind == RequestHead::Kind::kTile) {
          // (An empty or malformed tile path is the tile answer's 400.)
          try {
            ParseTilePath(h.tile_path);
          } catch (const ApiError& e) {
            ASSERT_EQ(e.status(), 400) << fz.Where() << ": " << Show(bytes);
          }
        }
        break;
      case RequestHead::Kind::kRefuse:
        ASSERT_TRUE(h.status == 400 || h.status == 411 || h.status == 414 || h.status == 431 || h.status == 501 ||
                    h.status == 505)
            << fz.Where() << ": " << h.status;
        ASSERT_NE(std::string(h.error), "") << fz.Where();
        break;
    }
    // A verdict is the same however many bytes had arrived when it was
    // given: a shorter prefix waits for more or says the same.
    const size_t cut = fz.Below(bytes.size() + 1);
    const RequestHead p = ParseRequestHead(std::string_view(bytes).substr(0, cut), limits);
    if (p.kind != RequestHead::Kind::kNeedMore) {
      ASSERT_EQ(KindName(p.kind), KindName(h.kind)) << fz.Where() << " at " << cut << ": " << p.error;
      ASSERT_EQ(p.size, h.size) << fz.Where();
      ASSERT_EQ(p.status, h.status) << fz.Where();
    }
  }
}

// A chunked body with random chunks, sizes in either case, leading zeros
// and extensions; its decoded length in `body`.
std::string ChunkedBody(Fuzzer& fz, size_t* body) {
  std::string out;
  *body = 0;
  const size_t chunks = fz.Below(6);
  for (size_t i = 0; i < chunks; ++i) {
    const size_t n = 1 + fz.Below(fz.OneIn(4) ? 40000 : 300);
    out += (fz.OneIn(4) ? "00" : "") + Hex(n, fz.OneIn(2)) + (fz.OneIn(4) ? ";name=value" : "") + "\r\n";
    out += std::string(n, 'x') + "\r\n";
    *body += n;
  }
  return out + "0\r\n\r\n";
}

struct ChunkVerdict {
  size_t used;
  bool done, refused;
  int status;
  size_t body;
  bool operator==(const ChunkVerdict& o) const {
    return used == o.used && done == o.done && refused == o.refused && status == o.status && body == o.body;
  }
};

ChunkVerdict FeedChunks(const std::string& bytes, size_t max, size_t piece) {
  ChunkedRequestBody b(max);
  size_t used = 0;
  for (size_t at = 0; at < bytes.size() && !b.done() && !b.refused(); at += piece) {
    const std::string_view part = std::string_view(bytes).substr(at, piece);
    const size_t n = b.Feed(part);
    if (n > part.size()) return {SIZE_MAX, false, false, 0, 0};
    used += n;
    if (n < part.size()) break;
  }
  return {used, b.done(), b.refused(), b.refused() ? b.status() : 0, b.body_bytes()};
}

TEST(Fuzz, ChunkedRequestBodies) {
  Fuzzer fz;
  while (fz.Next()) {
    const size_t max = fz.OneIn(2) ? 64 * 1024 : 1 + fz.Below(2000);
    size_t body = 0;
    const std::string valid = ChunkedBody(fz, &body);
    const std::string next = "GET /tiles/3/4/2.png HTTP/1.1\r\n\r\n";
    const bool mutated = !fz.OneIn(3);
    const std::string bytes = fz.OneIn(6) ? fz.Bytes(200) : mutated ? fz.Mutate(valid + next) : valid + next;
    const ChunkVerdict whole = FeedChunks(bytes, max, bytes.size() + 1);
    ASSERT_LE(whole.used, bytes.size()) << fz.Where();
    ASSERT_LE(whole.body, max) << fz.Where() << ": read past the limit";
    if (whole.refused) {
      ASSERT_TRUE(whole.status == 400 || whole.status == 413) << fz.Where();
    }
    if (bytes == valid + next) {
      if (body <= max) {
        ASSERT_TRUE(whole.done) << fz.Where();
        ASSERT_EQ(whole.used, valid.size()) << fz.Where();
        ASSERT_EQ(whole.body, body) << fz.Where();
      } else {
        ASSERT_TRUE(whole.refused && whole.status == 413) << fz.Where();
      }
    }
    // However the bytes arrive, the same verdict at the same byte.
    const size_t piece = 1 + fz.Below(fz.OneIn(3) ? 8 : 5000);
    ASSERT_TRUE(FeedChunks(bytes, max, piece) == whole) << fz.Where() << " in pieces of " << piece;
  }
}

// A response httplib could send, with an interim 100 before it at times.
std::string Response(Fuzzer& fz, bool head) {
  std::string out = fz.OneIn(5) ? "HTTP/1.1 100 Continue\r\n\r\n" : "";
  const int status = fz.Pick(std::vector<int>{200, 201, 204, 304, 400, 404, 413});
  out += "HTTP/1.1 " + std::to_string(status) + " X\r\nContent-Type: application/json\r\n";
  if (fz.OneIn(6)) out += "Connection: close\r\n";
  const std::string body(fz.Below(500), 'b');
  if (status == 204 || status == 304) return out + "\r\n";
  if (fz.OneIn(2)) return out + "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + (head ? "" : body);
  out += "Transfer-Encoding: chunked\r\n\r\n";
  if (head) return out;
  for (size_t at = 0; at < body.size(); at += 100)
    out += Hex(std::min<size_t>(100, body.size() - at), false) + "\r\n" + body.substr(at, 100) + "\r\n";
  return out + "0\r\n" + (fz.OneIn(3) ? "X-Trailer: 1\r\n" : "") + "\r\n";
}

struct FrameVerdict {
  size_t used;
  bool done, lost, close;
  // Once lost, all that follows is relayed: how much was fed last is not a verdict.
  bool operator==(const FrameVerdict& o) const {
    return (lost || used == o.used) && done == o.done && lost == o.lost && close == o.close;
  }
};

FrameVerdict FeedResponse(const std::string& bytes, bool head, size_t piece) {
  ResponseFramer f(head);
  size_t used = 0;
  for (size_t at = 0; at < bytes.size() && !f.done() && !f.lost(); at += piece) {
    const std::string_view part = std::string_view(bytes).substr(at, piece);
    const size_t n = f.Feed(part);
    if (n > part.size()) return {SIZE_MAX, false, false, false};
    used += n;
    if (n < part.size()) break;
  }
  return {used, f.done(), f.lost(), f.close()};
}

TEST(Fuzz, ResponseFraming) {
  Fuzzer fz;
  while (fz.Next()) {
    const bool head = fz.OneIn(4);
    const std::string valid = Response(fz, head);
    const std::string next = "HTTP/1.1 204 No Content\r\n\r\n";
    const bool mutated = !fz.OneIn(3);
    const std::string bytes = fz.OneIn(6) ? fz.Bytes(300) : mutated ? fz.Mutate(valid + next) : valid + next;
    const FrameVerdict whole = FeedResponse(bytes, head, bytes.size() + 1);
    ASSERT_LE(whole.used, bytes.size()) << fz.Where();
    if (bytes == valid + next) {
      ASSERT_TRUE(whole.done) << fz.Where() << ": " << Show(valid);
      ASSERT_EQ(whole.used, valid.size()) << fz.Where() << ": " << Show(valid);
    }
    const size_t piece = 1 + fz.Below(fz.OneIn(3) ? 8 : 1000);
    const FrameVerdict pieces = FeedResponse(bytes, head, piece);
    ASSERT_TRUE(pieces == whole) << fz.Where() << " in pieces of " << piece << ": " << Show(bytes)
                                 << (head ? " (HEAD)" : "") << ": used " << pieces.used << " vs " << whole.used
                                 << ", done " << pieces.done << " vs " << whole.done << ", lost " << pieces.lost
                                 << " vs " << whole.lost;
  }
}

TEST(Fuzz, HttpTokensAndOrigins) {
  Fuzzer fz;
  const std::vector<std::string> origins = {"http://127.0.0.1:8080", "https://Ship.Example:443", "http://[::1]:3000",
                                            "null", "http://evil.example"};
  const OriginPolicy policy({"http://10.0.0.5:3000"});
  while (fz.Next()) {
    const std::string s = fz.OneIn(2) ? fz.Bytes(30) : fz.Mutate(" Keep-Alive ,\tclose, upgrade ");
    const std::string_view t = TrimSpace(s);
    ASSERT_TRUE(t.empty() || (t.front() != ' ' && t.front() != '\t' && t.back() != ' ' && t.back() != '\t'))
        << fz.Where();
    ASSERT_NE(std::string_view(s).find(t), std::string_view::npos) << fz.Where();
    std::string lower(s);
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    ASSERT_TRUE(IEquals(s, lower)) << fz.Where();
    // HasToken against the list split by hand.
    bool listed = false;
    std::stringstream items(s);
    for (std::string item; std::getline(items, item, ',');) {
      const std::string_view trimmed = TrimSpace(item);
      std::string lowered(trimmed);
      for (char& c : lowered) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      listed = listed || lowered == "close";
    }
    ASSERT_EQ(HasToken(s, "close"), listed) << fz.Where() << ": " << Show(s);

    const std::string origin = fz.OneIn(3) ? fz.Bytes(30) : fz.Mutate(fz.Pick(origins));
    if (auto n = NormalizeOrigin(origin)) {
      ASSERT_EQ(NormalizeOrigin(*n), n) << fz.Where() << ": not idempotent for " << Show(origin);
      for (char c : *n) ASSERT_FALSE(std::isupper(static_cast<unsigned char>(c))) << fz.Where();
      const std::string host = n->substr(n->find("://") + 3);
      if (n->rfind("http://", 0) == 0) {
        ASSERT_FALSE(policy.RefuseWrite(host, origin, "cross-site")) << fz.Where();
      }
    } else if (!NormalizeOrigin(TrimSpace(origin))) {
      ASSERT_TRUE(policy.RefuseWrite("127.0.0.1:8080", origin, std::nullopt)) << fz.Where() << ": " << Show(origin);
    }
  }
}

TEST(Fuzz, Utf8AgreesWithTheJsonParser) {
  const std::vector<std::string> pieces = {
      "a", "\xc3\xa9", "\xe2\x82\xac", "\xf0\x9f\x90\x9f", "\xef\xbf\xbf", "\xed\x9f\xbf", "\xf4\x8f\xbf\xbf"};
  Fuzzer fz;
  while (fz.Next()) {
    std::string s;
    const size_t n = fz.Below(12);
    for (size_t i = 0; i < n; ++i) s += fz.OneIn(4) ? fz.Bytes(3) : fz.Pick(pieces);
    if (fz.OneIn(2)) s = fz.Mutate(s);
    // Bytes JSON would want escaped become plain letters (the offsets stay).
    for (char& c : s)
      if (static_cast<unsigned char>(c) < 0x20 || c == '"' || c == '\\') c = 'q';
    const bool json_ok = nlohmann::json::accept("\"" + s + "\"");
    const auto bad = FirstInvalidUtf8(s);
    ASSERT_EQ(!bad, json_ok) << fz.Where() << ": " << Show(s);
    if (bad) {
      ASSERT_FALSE(FirstInvalidUtf8(s.substr(0, *bad))) << fz.Where() << ": the text before is UTF-8";
    }
  }
}

// --- a real server -----------------------------------------------------------------------

using http_test::HttpServerTest;

TEST_F(HttpServerTest, FuzzedRequestsGetHttpAnswersAndTheServerGoesOn) {
  Start();
  const std::string mark = Mark(5, 43, "fuzz").dump();
  const std::vector<std::string> seeds = {
      "GET /tiles/3/4/2.png HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n",
      "GET /tiles/3/4/2.png HTTP/1.1\r\nHost: x\r\n\r\nGET /api/status HTTP/1.1\r\nHost: x\r\n\r\n",
      "GET /api/frames?lat=43&lon=5 HTTP/1.1\r\nHost: x\r\n\r\n",
      "GET /tiles.json HTTP/1.1\r\nHost: x\r\n\r\n",
      "GET /js/app.js HTTP/1.0\r\n\r\n",
      "POST /api/detections HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: " +
          std::to_string(mark.size()) + "\r\n\r\n" + mark,
      "POST /api/detections HTTP/1.1\r\nHost: x\r\nOrigin: http://evil.example\r\nTransfer-Encoding: chunked\r\n\r\n" +
          Hex(mark.size(), false) + "\r\n" + mark + "\r\n0\r\n\r\n",
      "PATCH /api/detections/2 HTTP/1.1\r\nHost: x\r\nContent-Length: 13\r\n\r\n{\"note\":\"n\"}\n",
      "DELETE /api/detections/99 HTTP/1.1\r\nHost: x\r\n\r\n",
      "OPTIONS /api/detections HTTP/1.1\r\nHost: x\r\nOrigin: http://a.example\r\n\r\n"};
  Fuzzer fz;
  while (fz.Next()) {
    std::string bytes = fz.OneIn(8) ? fz.Bytes(200) : fz.Mutate(fz.Pick(seeds));
    if (bytes.find("HEAD") != std::string::npos) continue;  // answers without a body: not followed here
    raw_http::Connection c(server_->port(), 10);
    ASSERT_TRUE(c.connected()) << fz.Where();
    c.Send(bytes);  // the server may close before it has all
    c.ShutdownWrite();
    ASSERT_TRUE(c.ReadToEnd()) << fz.Where() << ": no end within 10 s for " << Show(bytes);
    // Everything that came back is a sequence of well-formed answers.
    std::string_view rest = c.buffer();
    while (!rest.empty()) {
      raw_http::Response r;
      size_t used = 0;
      const raw_http::Parsed p = raw_http::ParseResponse(rest, false, true, &r, &used);
      ASSERT_EQ(p, raw_http::Parsed::kOk) << fz.Where() << ": " << Show(bytes) << " got " << Show(rest.substr(0, 300));
      ASSERT_TRUE(r.status >= 100 && r.status <= 599) << fz.Where();
      rest.remove_prefix(used);
    }
  }
  EXPECT_EQ(GetJson("/api/status")["name"], "Test mission") << "the server goes on";
}

}  // namespace
}  // namespace seamap::server
