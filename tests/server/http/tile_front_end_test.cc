// The tile front end over real sockets, in front of a real HttpServer:
// pipelining, keep-alive, HTTP/1.0, partial reads, slow readers, oversized
// and malformed heads, mixed tile and API pipelines, a randomised corpus.
// No assertion here is about time: every wait is a generous hang detector.
#include <poll.h>

#include <chrono>
#include <cstdlib>
#include <iostream>
#include <random>

#include "tests/server/http_test_fixture.h"
#include "tests/server/raw_http.h"

namespace seamap::server {
namespace {

using namespace http_test;
using raw_http::Connection;
using raw_http::Parsed;
using raw_http::Response;

std::string GetRequest(const std::string& target, const std::string& fields = "") {
  return "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n" + fields + "\r\n";
}

// Bytes as a C string literal would show them, for failure messages.
std::string Escaped(const std::string& bytes, size_t max = 400) {
  std::string out;
  for (unsigned char c : bytes.substr(0, max)) {
    if (c == '\r')
      out += "\\r";
    else if (c == '\n')
      out += "\\n";
    else if (c < 0x20 || c >= 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    } else
      out += static_cast<char>(c);
  }
  return bytes.size() > max ? out + "... (" + std::to_string(bytes.size()) + " bytes)" : out;
}

class TileFrontEndTest : public HttpServerTest {
 protected:
  std::string Tile(int z, int x, int y) const { return Text(mission_.tiles.at(TileId{z, x, y})); }
  int port() const { return server_->port(); }

  // A fresh connection still gets a tile: the server survived what came before.
  void ExpectServing(const std::string& after) {
    Connection c(port());
    ASSERT_TRUE(c.Send(GetRequest("/tiles/3/4/2.png"))) << after;
    auto r = c.Next();
    ASSERT_TRUE(r) << after;
    EXPECT_EQ(r->status, 200) << after;
    EXPECT_EQ(r->body, Tile(3, 4, 2)) << after;
  }
};

TEST_F(TileFrontEndTest, PipelinedRequestsAreAnsweredInOrder) {
  Start();
  const std::string etag = QuotedVersion(mission_.tiles.at(TileId{3, 4, 2}));
  struct Case {
    std::string request;
    int status;
    std::optional<std::string> body;  // not checked when absent
    bool head = false;
  };
  const std::vector<Case> cases = {
      {GetRequest("/tiles/3/4/2.png"), 200, Tile(3, 4, 2)},
      {GetRequest("/tiles/3/4/3.png?v=1"), 200, Tile(3, 4, 3)},
      {GetRequest("/tiles/3/7/7.png"), 204, ""},
      {GetRequest("/tiles/3/4/2.png", "If-None-Match: " + etag + "\r\n"), 304, ""},
      {GetRequest("/tiles/31/0/0.png"), 400, std::nullopt},
      {"HEAD /tiles/2/2/1.png HTTP/1.1\r\n\r\n", 200, "", true},
      {GetRequest("/tiles/enhanced/3/4/2.png"), 200, Text(mission_.enhanced.at(TileId{3, 4, 2}))},
      {GetRequest("/tiles/3/4/2.jpg"), 404, std::nullopt},
  };
  std::string burst;
  for (int round = 0; round < 10; ++round)
    for (const Case& c : cases) burst += c.request;
  Connection c(port());
  ASSERT_TRUE(c.Send(burst));
  for (int round = 0; round < 10; ++round) {
    for (const Case& expected : cases) {
      auto r = c.Next(expected.head);
      ASSERT_TRUE(r) << round << ": " << Escaped(expected.request) << " " << Escaped(c.buffer());
      EXPECT_EQ(r->status, expected.status) << Escaped(expected.request);
      if (expected.body) {
        EXPECT_EQ(r->body, *expected.body) << Escaped(expected.request);
      }
      if (expected.head) {
        EXPECT_EQ(r->Header("Content-Length"), std::to_string(mission_.tiles.at({2, 2, 1}).size()));
      }
    }
  }
  EXPECT_FALSE(c.closed());
}

TEST_F(TileFrontEndTest, OneConnectionKeepsServingManyRequests) {
  Start();
  Connection c(port());
  for (int i = 0; i < 300; ++i) {
    const bool odd = i % 2;
    ASSERT_TRUE(c.Send(GetRequest(odd ? "/tiles/3/4/3.png" : "/tiles/2/2/1.png"))) << i;
    auto r = c.Next();
    ASSERT_TRUE(r) << i;
    ASSERT_EQ(r->status, 200) << i;
    ASSERT_EQ(r->body, odd ? Tile(3, 4, 3) : Tile(2, 2, 1)) << i;
    ASSERT_EQ(r->Header("Connection"), "") << "HTTP/1.1 keeps the connection without saying so";
  }
  EXPECT_FALSE(c.closed());
}

TEST_F(TileFrontEndTest, Http10ClosesUnlessAskedToKeepAlive) {
  Start();
  for (const std::string target : {"/tiles/3/4/2.png", "/api/status"}) {
    Connection c(port());
    ASSERT_TRUE(c.Send("GET " + target + " HTTP/1.0\r\n\r\n"));
    auto r = c.Next();
    ASSERT_TRUE(r) << target;
    EXPECT_EQ(r->status, 200) << target;
    EXPECT_TRUE(c.ReadToEnd()) << target << ": an HTTP/1.0 answer ends the connection";
    EXPECT_EQ(c.buffer(), "") << target;
  }
  Connection kept(port());
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(kept.Send("GET /tiles/3/4/2.png HTTP/1.0\r\nConnection: keep-alive\r\n\r\n"));
    auto r = kept.Next();
    ASSERT_TRUE(r) << i;
    EXPECT_EQ(r->body, Tile(3, 4, 2));
    EXPECT_EQ(r->Header("Connection"), "keep-alive") << "else an HTTP/1.0 client waits for the close";
  }
  Connection closing(port());
  ASSERT_TRUE(closing.Send(GetRequest("/tiles/3/4/2.png", "Connection: close\r\n") + GetRequest("/tiles/3/4/3.png")));
  auto r = closing.Next();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->Header("Connection"), "close");
  EXPECT_TRUE(closing.ReadToEnd());
  EXPECT_EQ(closing.buffer(), "") << "nothing is answered after a close";
}

TEST_F(TileFrontEndTest, RequestsArrivingInPiecesAreAnswered) {
  Start();
  Connection c(port());
  // One byte at a time: tiles and an API request, pipelined.
  const std::string bytes = GetRequest("/tiles/3/4/2.png") + GetRequest("/api/status") + GetRequest("/tiles/3/4/3.png");
  for (char b : bytes) {
    ASSERT_TRUE(c.Send(std::string(1, b)));
    std::this_thread::sleep_for(std::chrono::microseconds(300));  // pacing, so the server reads pieces
  }
  auto tile = c.Next(), status = c.Next(), tile2 = c.Next();
  ASSERT_TRUE(tile && status && tile2) << Escaped(c.buffer());
  EXPECT_EQ(tile->body, Tile(3, 4, 2));
  EXPECT_EQ(status->status, 200);
  EXPECT_EQ(json::parse(status->body)["name"], "Test mission");
  EXPECT_EQ(tile2->body, Tile(3, 4, 3));

  // A tile request split at every position, on one connection.
  Connection split(port());
  const std::string request = GetRequest("/tiles/2/2/1.png", "If-None-Match: \"x\"\r\n");
  for (size_t at = 1; at < request.size(); ++at) {
    ASSERT_TRUE(split.Send(request.substr(0, at)));
    std::this_thread::sleep_for(std::chrono::microseconds(500));
    ASSERT_TRUE(split.Send(request.substr(at)));
    auto r = split.Next();
    ASSERT_TRUE(r) << at;
    ASSERT_EQ(r->body, Tile(2, 2, 1)) << at;
  }
}

TEST_F(TileFrontEndTest, AClientThatStopsReadingDoesNotHoldUpOthers) {
  Start();
  // 40,000 pipelined requests (~13 MB of answers) from a client that reads
  // nothing until the others are done: the server stops reading it.
  Connection slow(port(), 60, 4096);
  std::string burst;
  for (int i = 0; i < 40000; ++i) burst += "GET /tiles/3/4/2.png HTTP/1.1\r\n\r\n";
  std::atomic<bool> sent{false};
  std::thread sender([&] { sent = slow.Send(burst); });
  for (int k = 0; k < 4; ++k) {
    Connection other(port());
    for (int i = 0; i < 25; ++i) {
      ASSERT_TRUE(other.Send(GetRequest("/tiles/3/4/3.png"))) << k << " " << i;
      auto r = other.Next();
      ASSERT_TRUE(r) << k << " " << i;
      ASSERT_EQ(r->body, Tile(3, 4, 3));
    }
    auto status = Get("/api/status");  // the backend too
    ASSERT_TRUE(status);
    EXPECT_EQ(status->status, 200);
  }
  // Once it reads, it gets every answer, in order.
  for (int i = 0; i < 40000; ++i) {
    auto r = slow.Next();
    ASSERT_TRUE(r) << i;
    ASSERT_EQ(r->body, Tile(3, 4, 2)) << i;
  }
  sender.join();
  EXPECT_TRUE(sent);
}

TEST_F(TileFrontEndTest, OversizedHeadsAreRefusedAndTheConnectionEnds) {
  Start();
  std::string fields;  // many small fields, 20 KiB in all
  for (int i = 0; i < 400; ++i) fields += "X-Field-" + std::to_string(i) + ": " + std::string(40, 'v') + "\r\n";
  const std::vector<std::pair<std::string, int>> cases = {
      {GetRequest("/tiles/" + std::string(20000, '1') + ".png"), 414},
      {GetRequest("/tiles/3/4/2.png?v=" + std::string(20000, 'a')), 414},
      {GetRequest("/api/status?x=" + std::string(20000, 'a')), 414},
      {GetRequest("/tiles/3/4/2.png", "X-Big: " + std::string(20000, 'c') + "\r\n"), 431},
      {GetRequest("/api/status", fields), 431},
  };
  for (const auto& [request, status] : cases) {
    Connection c(port());
    c.Send(request);  // the server may answer and close before it has read everything
    auto r = c.Next();
    ASSERT_TRUE(r) << Escaped(request, 80) << " -> " << Escaped(c.buffer());
    EXPECT_EQ(r->status, status) << Escaped(request, 80);
    EXPECT_EQ(r->Header("Connection"), "close");
    EXPECT_TRUE(c.ReadToEnd());
  }
  // Long, but within the limits: answered.
  Connection c(port());
  ASSERT_TRUE(
      c.Send(GetRequest("/api/status?x=" + std::string(8000, 'a'), fields.substr(0, fields.find("\r\n", 7000) + 2))));
  auto r = c.Next();
  ASSERT_TRUE(r) << Escaped(c.buffer());
  EXPECT_EQ(r->status, 200);
  ExpectServing("oversized heads");
}

TEST_F(TileFrontEndTest, MalformedRequestsGetA4xxAndTheConnectionEnds) {
  Start();
  for (const std::string request : {
           "GET  /tiles/3/4/2.png HTTP/1.1\r\n\r\n",
           "GET /tiles/3/4/2.png\r\n\r\n",
           "GET /tiles/3/4/2.png HTTP/1.1 x\r\n\r\n",
           "GET /tiles/3/4/2.png HTTP/1.1\n\n",
           "FOO\r\n\r\n",
           "\x01\x02\x03\r\n\r\n",
           "GET /tiles/3/4/2.png HTTP/1.1\r\nHost x\r\n\r\n",
           "GET /api/status HTTP/1.1\r\nHost: x\r\n folded\r\n\r\n",
           "GET /tiles/3/4/2.png HTTP/1.1\r\nContent-Length: abc\r\n\r\n",
       }) {
    Connection c(port());
    ASSERT_TRUE(c.Send(request + GetRequest("/tiles/3/4/2.png")));
    auto r = c.Next();
    ASSERT_TRUE(r) << Escaped(request) << " -> " << Escaped(c.buffer());
    EXPECT_EQ(r->status, 400) << Escaped(request);
    EXPECT_EQ(r->Header("Connection"), "close");
    EXPECT_NE(json::parse(r->body)["error"].get<std::string>().find("bad request: "), std::string::npos);
    EXPECT_TRUE(c.ReadToEnd()) << Escaped(request);
    EXPECT_EQ(c.buffer(), "") << "nothing after: where the next request starts is unknown";
  }
  Connection other_version(port());
  ASSERT_TRUE(other_version.Send("GET /tiles/3/4/2.png HTTP/9.9\r\n\r\n"));
  auto r = other_version.Next();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 505);
  // Dot segments and escapes go to httplib, which refuses them (never a file outside).
  for (const std::string target : {"/tiles/../secret.txt", "/tiles/%2e%2e/%2e%2e/secret.txt", "/../secret.txt"}) {
    Connection c(port());
    ASSERT_TRUE(c.Send(GetRequest(target)));
    auto r = c.Next();
    ASSERT_TRUE(r) << target;
    EXPECT_GE(r->status, 400) << target;
    EXPECT_LT(r->status, 500) << target;
    EXPECT_EQ(r->body.find("TOP SECRET"), std::string::npos) << target;
  }
  ExpectServing("malformed requests");
}

TEST_F(TileFrontEndTest, AMixedPipelineOfTilesAndApiRequestsIsAnsweredInOrder) {
  Start();
  const std::string etag = QuotedVersion(mission_.tiles.at(TileId{3, 4, 2}));
  std::string burst = GetRequest("/tiles/3/4/2.png") + GetRequest("/api/status") + GetRequest("/tiles/3/4/3.png") +
                      GetRequest("/tiles.json") + "HEAD /tiles/2/2/1.png HTTP/1.1\r\n\r\n" +
                      GetRequest("/api/frames/99999") +
                      GetRequest("/tiles/3/4/2.png", "If-None-Match: " + etag + "\r\n") + GetRequest("/api/nope") +
                      GetRequest("/tiles/3/4/2.png");
  Connection c(port());
  ASSERT_TRUE(c.Send(burst));
  struct Expected {
    int status;
    std::string body;  // a tile's bytes, or a text the JSON body contains
    bool head = false;
  };
  for (const Expected& e : std::vector<Expected>{{200, Tile(3, 4, 2)},
                                                 {200, "\"name\":\"Test mission\""},
                                                 {200, Tile(3, 4, 3)},
                                                 {200, "\"tilejson\":\"3.0.0\""},
                                                 {200, "", true},
                                                 {404, "no frame 99999"},
                                                 {304, ""},
                                                 {404, "no such API endpoint"},
                                                 {200, Tile(3, 4, 2)}}) {
    auto r = c.Next(e.head);
    ASSERT_TRUE(r) << e.status << " " << Escaped(e.body, 40) << ": " << Escaped(c.buffer());
    EXPECT_EQ(r->status, e.status);
    EXPECT_NE(r->body.find(e.body), std::string::npos) << Escaped(r->body);
  }
}

TEST_F(TileFrontEndTest, ChunkedAndExpectContinueUploadsReachHttplib) {
  Start();
  const std::string chunked = Mark(5.0, 43.0, "chunked").dump();
  char size[16];
  std::snprintf(size, sizeof size, "%zx", chunked.size());
  Connection c(port());
  ASSERT_TRUE(
      c.Send("POST /api/detections HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
             "Transfer-Encoding: chunked\r\n\r\n" +
             std::string(size) + "\r\n" + chunked + "\r\n0\r\n\r\n"));
  auto r = c.Next();
  ASSERT_TRUE(r) << Escaped(c.buffer());
  EXPECT_EQ(r->status, 201) << r->body;

  const std::string expecting = Mark(5.0, 43.0, "expect").dump();
  Connection e(port());
  ASSERT_TRUE(
      e.Send("POST /api/detections HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
             "Expect: 100-continue\r\nContent-Length: " +
             std::to_string(expecting.size()) + "\r\n\r\n"));
  auto go_on = e.Next();
  ASSERT_TRUE(go_on) << Escaped(e.buffer());
  EXPECT_EQ(go_on->status, 100);
  ASSERT_TRUE(e.Send(expecting));
  auto created = e.Next();
  ASSERT_TRUE(created) << Escaped(e.buffer());
  EXPECT_EQ(created->status, 201) << created->body;
  ASSERT_TRUE(e.Send(GetRequest("/tiles/3/4/2.png")));  // the same connection, a tile again
  auto tile = e.Next();
  ASSERT_TRUE(tile);
  EXPECT_EQ(tile->body, Tile(3, 4, 2));
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?class=chunked,expect")).size(), 2u);
}

// Random mutations of valid requests: the server never crashes, every
// connection gets well-formed responses or is closed, and a valid request on
// a fresh connection still works. A fixed seed first, then a fresh one
// (printed; SEAMAP_FUZZ_SEED replays it). Eight connections at a time: a
// connection relayed byte for byte ends only when httplib's keep-alive does.
TEST_F(TileFrontEndTest, ARandomisedCorpusNeverBreaksTheServer) {
  Start();
  const std::string body = Mark(5.005, 43.005, "fuzz").dump();
  const std::vector<std::string> templates = {
      GetRequest("/tiles/3/4/2.png"),
      GetRequest("/tiles/enhanced/3/4/2.png", "If-None-Match: \"0123456789abcdef\", W/\"x\"\r\n"),
      "GET /tiles/3/4/3.png?v=1 HTTP/1.0\r\nConnection: keep-alive\r\n\r\n",
      GetRequest("/api/status", "Accept-Encoding: gzip\r\n"),
      GetRequest("/tiles.json"),
      GetRequest("/api/frames?lat=43.005&lon=5.005"),
      GetRequest("/index.html"),
      GetRequest("/api/detections?bbox=4,42,6,44"),
      "POST /api/detections HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\nContent-Length: " +
          std::to_string(body.size()) + "\r\n\r\n" + body,
  };
  const std::string interesting = std::string(
                                      "\r\n :/.%?#\t\x7f\xff"
                                      "A0",
                                      14) +
                                  std::string(1, '\0');
  auto mutate = [&](std::mt19937_64& random) {
    auto pick = [&](size_t n) { return n == 0 ? 0 : static_cast<size_t>(random() % n); };
    std::string s = templates[pick(templates.size())];
    for (int m = 0, n = 1 + static_cast<int>(pick(4)); m < n; ++m) {
      const size_t at = pick(s.size() + 1);
      const char byte = random() % 2 ? interesting[pick(interesting.size())] : static_cast<char>(random());
      switch (pick(9)) {
        case 0:
          if (at < s.size()) s[at] = byte;
          break;
        case 1:
          s.insert(at, 1, byte);
          break;
        case 2:
          s.erase(std::min(at, s.size()), 1);
          break;
        case 3:
          s.erase(std::min(at, s.size()), pick(20));
          break;
        case 4:
          s.insert(at, s.substr(std::min(at, s.size()), pick(30)));
          break;
        case 5:
          s.insert(at, 1000 + pick(20000), byte);  // past the limits
          break;
        case 6:
          for (size_t p; (p = s.find("\r\n")) != std::string::npos;) s.replace(p, 2, "\n");
          break;
        case 7:
          s += templates[pick(templates.size())];  // pipelined
          break;
        default:
          s.resize(at);
          break;
      }
    }
    return s;
  };

  struct Case {
    std::string request, what;
    std::unique_ptr<Connection> connection;
    std::chrono::steady_clock::time_point deadline;
  };
  int cases = 0, responses = 0;
  // Everything that came back must be a sequence of whole responses.
  auto check = [&](const Case& c) {
    std::string_view rest = c.connection->buffer();
    while (!rest.empty()) {
      Response r;
      size_t used = 0;
      const Parsed p = raw_http::ParseResponse(rest, false, true, &r, &used);
      ASSERT_EQ(p, Parsed::kOk) << c.what << "\n got: " << Escaped(std::string(rest));
      ASSERT_TRUE(r.status >= 100 && r.status < 600) << c.what;
      rest.remove_prefix(used);
      ++responses;
    }
  };
  auto run = [&](uint64_t seed, std::chrono::milliseconds budget) {
    std::mt19937_64 random(seed);
    const auto end = std::chrono::steady_clock::now() + budget;
    std::vector<Case> open;
    for (int i = 0; std::chrono::steady_clock::now() < end || !open.empty();) {
      while (open.size() < 8 && std::chrono::steady_clock::now() < end) {
        Case c;
        c.request = mutate(random);
        c.what = "seed " + std::to_string(seed) + " case " + std::to_string(i++) + ": " + Escaped(c.request);
        c.connection = std::make_unique<Connection>(port(), 20);
        ASSERT_TRUE(c.connection->connected()) << c.what;
        c.connection->Send(c.request);  // the server may answer and close before it has read everything
        c.connection->ShutdownWrite();
        c.deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        open.push_back(std::move(c));
        ++cases;
      }
      std::vector<pollfd> fds;
      for (const Case& c : open) fds.push_back({c.connection->fd(), POLLIN, 0});
      ::poll(fds.data(), fds.size(), 100);
      for (size_t k = open.size(); k-- > 0;) {
        Case& c = open[k];
        if (fds[k].revents) c.connection->ReceiveSome();
        ASSERT_LT(std::chrono::steady_clock::now(), c.deadline) << "neither answered nor closed: " << c.what;
        if (!c.connection->closed()) continue;
        check(c);
        if (::testing::Test::HasFatalFailure()) return;
        open.erase(open.begin() + static_cast<long>(k));
        if (cases % 50 == 0) ExpectServing(c.what);
      }
    }
  };
  run(20240611, std::chrono::milliseconds(1500));
  uint64_t seed = std::random_device{}();
  if (const char* env = std::getenv("SEAMAP_FUZZ_SEED")) seed = std::strtoull(env, nullptr, 10);
  std::cout << "randomised corpus: seed " << seed << " (SEAMAP_FUZZ_SEED replays it)" << std::endl;
  run(seed, std::chrono::milliseconds(1500));
  std::cout << "randomised corpus: " << cases << " connections, " << responses << " responses" << std::endl;
  ExpectServing("the randomised corpus");
}

}  // namespace
}  // namespace seamap::server
