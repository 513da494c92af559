// The server on a shared network, over real sockets: writes from other
// sites' pages (Origin), --allow-origin and CORS, the token check the
// console makes, symbolic links out of web/, bodies that are not UTF-8 and
// chunked bodies over the limit.
#include "tests/server/http_test_fixture.h"
#include "tests/server/raw_http.h"

namespace seamap::server {
namespace {

using namespace http_test;

std::string ChunkedHead(const std::string& target = "/api/detections") {
  return "POST " + target +
         " HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n";
}

std::string Chunk(const std::string& data) {
  char size[16];
  std::snprintf(size, sizeof size, "%zx", data.size());
  return std::string(size) + "\r\n" + data + "\r\n";
}

// --- bodies ---------------------------------------------------------------------------

TEST_F(HttpServerTest, BodiesThatAreNotUtf8Are400) {
  Start();
  auto client = Client();
  const std::string feature = R"({"type":"Feature","geometry":{"type":"Point","coordinates":[5,43]},)";
  struct Case {
    std::string body, what;
  };
  for (const Case& c : std::vector<Case>{
           {feature + "\"properties\":{\"class\":\"x\xff\"}}", "FF in a string"},
           {feature + "\"properties\":{\"class\":\"\xc0\xaf\"}}", "an overlong '/'"},
           {feature + "\"properties\":{\"class\":\"\xed\xa0\x80\"}}", "a surrogate"},
           {"\xfe\xff{}", "a UTF-16 byte order mark"},
           {feature + "\"properties\":{\"class\":\"caf\xc3\"}}", "cut short"},
       }) {
    auto res = client->Post("/api/detections", c.body, "application/json");
    ExpectError(res, 400, "not valid UTF-8", c.what);
  }
  ExpectError(client->Patch("/api/detections/2", "{\"note\":\"\xff\"}", "application/json"), 400, "UTF-8", "patch");
  // A message that quotes a client's bytes stays JSON.
  ExpectError(Get("/api/frames/%FF%FE"), 400, "frame id", "an id that is not UTF-8");
  EXPECT_EQ(StoredDetections().size(), 2u);
  // Real UTF-8 is stored as sent.
  json accented = Mark(5, 43, "\xc3\xa9pave");
  auto created = client->Post("/api/detections", accented.dump(), "application/json");
  ASSERT_TRUE(created);
  EXPECT_EQ(created->status, 201) << created->body;
  EXPECT_EQ(json::parse(created->body)["properties"]["class"], "\xc3\xa9pave");
}

TEST_F(HttpServerTest, AChunkedBodyWithinTheLimitIsServedAndTheConnectionGoesOn) {
  Start();
  const std::string mark = Mark(5.0, 43.0, "chunked").dump();
  raw_http::Connection c(server_->port());
  ASSERT_TRUE(c.Send(ChunkedHead() + Chunk(mark.substr(0, 10)) + Chunk(mark.substr(10)) + "0\r\n\r\n" +
                     "GET /tiles/3/4/2.png HTTP/1.1\r\nHost: x\r\n\r\n" + ChunkedHead() + Chunk(mark) + "0\r\n\r\n"));
  auto first = c.Next();
  ASSERT_TRUE(first) << c.buffer();
  EXPECT_EQ(first->status, 201) << first->body;
  auto tile = c.Next();
  ASSERT_TRUE(tile) << c.buffer();
  EXPECT_EQ(tile->status, 200);
  EXPECT_EQ(tile->body, Text(mission_.tiles.at(TileId{3, 4, 2}))) << "answered by the front end again";
  auto second = c.Next();
  ASSERT_TRUE(second) << c.buffer();
  EXPECT_EQ(second->status, 201) << second->body;
  EXPECT_FALSE(c.closed());
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?class=chunked")).size(), 2u);
}

TEST_F(HttpServerTest, AChunkedBodyOverTheLimitIs413AndTheConnectionCloses) {
  Start();
  // Many 1 KiB chunks: refused once they pass 64 KiB, the rest never read.
  raw_http::Connection many(server_->port());
  std::string chunks;
  for (int i = 0; i < 80; ++i) chunks += Chunk(std::string(1024, 'n'));
  many.Send(ChunkedHead() + chunks);  // the server may close before it has all
  auto r = many.Next();
  ASSERT_TRUE(r) << many.buffer().substr(0, 300);
  EXPECT_EQ(r->status, 413);
  EXPECT_EQ(r->Header("Content-Type"), "application/json");
  EXPECT_NE(r->body.find("over the limit of 64 KiB"), std::string::npos) << r->body;
  EXPECT_EQ(r->Header("Connection"), "close");
  EXPECT_TRUE(many.ReadToEnd()) << "the connection closes";

  // One chunk that says it is 1 MiB: refused from its size line alone.
  raw_http::Connection big(server_->port());
  big.Send(ChunkedHead() + "100000\r\n" + std::string(1000, '{'));
  auto b = big.Next();
  ASSERT_TRUE(b) << big.buffer().substr(0, 300);
  EXPECT_EQ(b->status, 413);
  EXPECT_TRUE(big.ReadToEnd());

  // With "Expect: 100-continue" (curl's way): the interim answer, then 413.
  raw_http::Connection expect(server_->port());
  ASSERT_TRUE(expect.Send(
      "POST /api/detections HTTP/1.1\r\nHost: x\r\nExpect: 100-continue\r\nTransfer-Encoding: chunked\r\n\r\n"));
  auto go_on = expect.Next();
  ASSERT_TRUE(go_on) << expect.buffer();
  EXPECT_EQ(go_on->status, 100);
  expect.Send(chunks);
  auto e = expect.Next();
  ASSERT_TRUE(e) << expect.buffer().substr(0, 300);
  EXPECT_EQ(e->status, 413);

  EXPECT_EQ(StoredDetections().size(), 2u);
  EXPECT_EQ(GetJson("/api/status")["name"], "Test mission") << "the server goes on";
}

TEST_F(HttpServerTest, AMalformedChunkedBodyIs400) {
  Start();
  raw_http::Connection c(server_->port());
  ASSERT_TRUE(c.Send(ChunkedHead() + "5\r\nhelloXX\r\n0\r\n\r\n"));
  auto r = c.Next();
  ASSERT_TRUE(r) << c.buffer();
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(r->body.find("not followed by CRLF"), std::string::npos) << r->body;
  EXPECT_TRUE(c.ReadToEnd());
  for (const std::string te : {"gzip, chunked", "identity"}) {
    raw_http::Connection t(server_->port());
    ASSERT_TRUE(t.Send("POST /api/detections HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: " + te + "\r\n\r\n"));
    auto n = t.Next();
    ASSERT_TRUE(n) << te;
    EXPECT_EQ(n->status, 501) << te;
  }
  EXPECT_EQ(StoredDetections().size(), 2u);
}

}  // namespace
}  // namespace seamap::server
