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

// --- the hostile-input table: one case per server item of issue 17 ------------------------

TEST_F(HttpServerTest, HostileInputTable) {
  std::filesystem::create_symlink(dir_ / "secret.txt", web_ / "leak.txt");
  ServerOptions o = Options();
  o.token = "s3cret";
  Start(o);
  const std::string mark = Mark(5, 43, "hostile").dump();
  std::string big_chunks;  // 96 KiB in 1 KiB chunks: the body limit is 64 KiB
  for (int i = 0; i < 96; ++i) big_chunks += Chunk(std::string(1024, 'a'));
  struct Case {
    const char* item;  // as the issue names it
    std::string request;
    int status;
    const char* error;  // in the JSON error
  };
  const std::vector<Case> cases = {
      {"a cross-site form-style POST (text/plain, another site's Origin)",
       "POST /api/detections HTTP/1.1\r\nHost: 127.0.0.1\r\nOrigin: http://evil.example\r\nContent-Type: "
       "text/plain\r\nAuthorization: Bearer s3cret\r\nContent-Length: " +
           std::to_string(mark.size()) + "\r\n\r\n" + mark,
       403, "cross-site write refused"},
      {"a wrong token, checked when entered (GET /api/auth)",
       "GET /api/auth HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer s3cre\r\n\r\n", 401, "wrong token"},
      {"a static file that is a symbolic link out of web/", "GET /leak.txt HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n", 404,
       "not found"},
      {"invalid UTF-8 in a request body",
       "POST /api/detections HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer s3cret\r\nContent-Type: "
       "application/json\r\nContent-Length: 13\r\n\r\n{\"class\":\"\xff\"}",
       400, "not valid UTF-8"},
      {"a chunked body over 64 KiB", ChunkedHead() + big_chunks, 413, "over the limit of 64 KiB"},
      {"a chunk that says it is 64 MiB", ChunkedHead() + "4000000\r\n" + std::string(1000, 'a'), 413,
       "over the limit of 64 KiB"},
  };
  for (const Case& c : cases) {
    raw_http::Connection conn(server_->port());
    conn.Send(c.request);  // the server may refuse before it has all
    conn.ShutdownWrite();
    auto r = conn.Next();
    ASSERT_TRUE(r) << c.item << ": " << conn.buffer().substr(0, 200);
    EXPECT_EQ(r->status, c.status) << c.item << ": " << r->body;
    EXPECT_EQ(r->Header("Content-Type"), "application/json") << c.item;
    const json body = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(body.is_object() && body.contains("error")) << c.item << ": " << r->body;
    EXPECT_NE(body["error"].get<std::string>().find(c.error), std::string::npos) << c.item << ": " << r->body;
    EXPECT_EQ(r->body.find("TOP SECRET"), std::string::npos) << c.item;
  }
  EXPECT_EQ(StoredDetections().size(), 2u) << "none of them wrote";
  EXPECT_EQ(GetJson("/api/status")["name"], "Test mission") << "the server goes on";
}

// --- writes from other sites' pages ---------------------------------------------------

// A write as a browser page sends it: its Origin and Sec-Fetch-Site fields.
httplib::Headers FromPage(const std::string& origin, const std::string& fetch_site = "") {
  httplib::Headers h;
  if (!origin.empty()) h.emplace("Origin", origin);
  if (!fetch_site.empty()) h.emplace("Sec-Fetch-Site", fetch_site);
  return h;
}

TEST_F(HttpServerTest, WritesFromOtherSitesPagesAre403) {
  Start();
  auto client = Client();
  const std::string own = "http://127.0.0.1:" + std::to_string(server_->port());
  const std::string mark = Mark(5, 43, "forged").dump();
  // The form-style POST of the review: text/plain, no preflight, no token needed.
  struct Case {
    httplib::Headers headers;
    const char* what;
  };
  for (const Case& c : std::vector<Case>{
           {FromPage("http://evil.example", "cross-site"), "another site"},
           {FromPage("http://127.0.0.1:" + std::to_string(server_->port() + 1), "same-site"), "another port"},
           {FromPage("null", "cross-site"), "a sandboxed frame"},
           {FromPage("", "cross-site"), "a browser that left Origin out"},
       }) {
    ExpectError(client->Post("/api/detections", c.headers, mark, "text/plain"), 403, "cross-site write refused",
                c.what);
    ExpectError(client->Patch("/api/detections/2", c.headers, R"({"note":"x"})", "application/json"), 403,
                "--allow-origin", c.what);
    ExpectError(client->Delete("/api/detections/2", c.headers), 403, "cross-site", c.what);
  }
  EXPECT_EQ(StoredDetections().size(), 2u);
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?class=forged")).size(), 0u);
  // Reading stays open to every page.
  auto read = client->Get("/api/status", FromPage("http://evil.example", "cross-site"));
  ASSERT_TRUE(read);
  EXPECT_EQ(read->status, 200);

  // The console's own pages and clients that are not browsers (curl) write.
  for (const Case& c : std::vector<Case>{{FromPage(own, "same-origin"), "the server's own page"},
                                         {FromPage("", "same-origin"), "own page, no Origin"},
                                         {{}, "curl"}}) {
    auto res = client->Post("/api/detections", c.headers, Mark(5, 43, "kept").dump(), "application/json");
    ASSERT_TRUE(res) << c.what;
    EXPECT_EQ(res->status, 201) << c.what << ": " << res->body;
  }
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?class=kept")).size(), 3u);
}

TEST_F(HttpServerTest, WritesFromOtherSitesAre403EvenWithTheToken) {
  ServerOptions o = Options();
  o.token = "s3cret";
  Start(o);
  httplib::Headers h = FromPage("http://evil.example", "cross-site");
  h.emplace("Authorization", "Bearer s3cret");
  ExpectError(Client()->Post("/api/detections", h, Mark(5, 43, "x").dump(), "application/json"), 403, "cross-site",
              "token and a foreign Origin");
  EXPECT_EQ(StoredDetections().size(), 2u);
}

TEST_F(HttpServerTest, AllowedOriginsWriteWithCors) {
  ServerOptions o = Options();
  o.allow_origins = {"http://dash.example:3000", "https://ops.example"};
  Start(o);
  auto client = Client();
  // The browser's preflight for a JSON POST with a token.
  httplib::Headers preflight = FromPage("http://dash.example:3000", "cross-site");
  preflight.emplace("Access-Control-Request-Method", "POST");
  preflight.emplace("Access-Control-Request-Headers", "authorization, content-type");
  auto pre = client->Options("/api/detections", preflight);
  ASSERT_TRUE(pre);
  EXPECT_EQ(pre->status, 204);
  EXPECT_EQ(pre->get_header_value("Access-Control-Allow-Origin"), "http://dash.example:3000");
  EXPECT_NE(pre->get_header_value("Access-Control-Allow-Methods").find("POST"), std::string::npos);
  EXPECT_NE(pre->get_header_value("Access-Control-Allow-Headers").find("Authorization"), std::string::npos);

  auto created = client->Post("/api/detections", FromPage("https://ops.example", "cross-site"),
                              Mark(5, 43, "integration").dump(), "application/json");
  ASSERT_TRUE(created);
  EXPECT_EQ(created->status, 201) << created->body;
  EXPECT_EQ(created->get_header_value("Access-Control-Allow-Origin"), "https://ops.example");
  EXPECT_EQ(created->get_header_value("Vary"), "Origin");

  // Origins not on the list get no CORS answer and no write.
  auto other = client->Post("/api/detections", FromPage("http://dash.example:3001", "cross-site"),
                            Mark(5, 43, "integration").dump(), "application/json");
  ExpectError(other, 403, "cross-site", "an origin not on the list");
  EXPECT_FALSE(other->has_header("Access-Control-Allow-Origin"));
  auto other_pre = client->Options("/api/detections", FromPage("http://evil.example", "cross-site"));
  ASSERT_TRUE(other_pre);
  EXPECT_FALSE(other_pre->has_header("Access-Control-Allow-Origin"));
  EXPECT_EQ(FeatureIds(GetJson("/api/detections?class=integration")).size(), 1u);
}

// --- the token, checked when entered ------------------------------------------------------

TEST_F(HttpServerTest, ApiAuthSaysWhetherATokenIsRight) {
  auto check = [this](const std::string& token) {
    httplib::Headers h;
    if (!token.empty()) h.emplace("Authorization", "Bearer " + token);
    return Client()->Get("/api/auth", h);
  };
  Start();
  for (const std::string token : {"", "anything"}) {
    auto open = check(token);
    ASSERT_TRUE(open);
    EXPECT_EQ(open->status, 204) << "no token configured: every token is fine";
  }
  server_->Stop();
  server_.reset();
  ServerOptions o = Options();
  o.token = "s3cret";
  Start(o);
  ExpectError(check(""), 401, "Authorization: Bearer", "no token");
  ExpectError(check("s3cre"), 401, "wrong token", "a wrong token");
  ExpectError(check("s3cretX"), 401, "wrong token", "a longer one");
  auto right = check("s3cret");
  ASSERT_TRUE(right);
  EXPECT_EQ(right->status, 204);
  EXPECT_EQ(right->get_header_value("Cache-Control"), "no-store");
  EXPECT_EQ(StoredDetections().size(), 2u) << "checking writes nothing";
}

// --- static files ----------------------------------------------------------------------

TEST_F(HttpServerTest, SymbolicLinksOutOfTheWebFolderAreNotFollowed) {
  namespace fs = std::filesystem;
  fs::create_symlink(dir_ / "secret.txt", web_ / "leak.txt");
  fs::create_symlink(dir_.path(), web_ / "up");
  fs::create_symlink("../../secret.txt", web_ / "js" / "relative.txt");
  fs::create_symlink("/etc/passwd", web_ / "passwd");
  fs::create_symlink(web_ / "js" / "app.js", web_ / "inside.js");  // inside: served
  fs::create_symlink(web_ / "nowhere", web_ / "dangling.js");
  Start();
  for (const std::string path : {"/leak.txt", "/up/secret.txt", "/js/relative.txt", "/passwd", "/%6Ceak.txt"}) {
    for (const bool head : {false, true}) {
      RawResponse r = head ? RawResponse{} : RawGet(server_->port(), path);
      if (head) {
        auto res = Client()->Head(path.c_str());
        ASSERT_TRUE(res) << path;
        r.status = res->status;
      }
      EXPECT_EQ(r.status, 404) << path << (head ? " (HEAD)" : "") << ": " << r.text;
      EXPECT_EQ(r.text.find("TOP SECRET"), std::string::npos) << path;
      EXPECT_EQ(r.text.find("root:"), std::string::npos) << path;
    }
  }
  auto inside = Get("/inside.js");
  ASSERT_TRUE(inside);
  EXPECT_EQ(inside->status, 200);
  EXPECT_EQ(inside->body, "console.log('seamap');");
  auto dangling = Get("/dangling.js");
  ASSERT_TRUE(dangling);
  EXPECT_EQ(dangling->status, 404);
  auto index = Get("/");
  ASSERT_TRUE(index);
  EXPECT_EQ(index->status, 200);
}

TEST_F(HttpServerTest, ACatalogueDoesNotFollowLinksOutOfTheWebFolderEither) {
  std::filesystem::create_symlink(dir_ / "secret.txt", web_ / "leak.txt");
  std::filesystem::create_directories(dir_ / "maps");
  HttpServer catalogue(Options(), (dir_ / "maps").string());
  catalogue.Bind();
  catalogue.Start();
  httplib::Client client("127.0.0.1", catalogue.port());
  auto leak = client.Get("/leak.txt");
  ASSERT_TRUE(leak);
  EXPECT_EQ(leak->status, 404);
  EXPECT_EQ(leak->body.find("TOP SECRET"), std::string::npos);
  auto js = client.Get("/js/app.js");
  ASSERT_TRUE(js);
  EXPECT_EQ(js->status, 200);
  catalogue.Stop();
}

TEST_F(HttpServerTest, AWebFolderThatIsItselfALinkIsServed) {
  std::filesystem::create_symlink(web_, dir_ / "web-link");
  ServerOptions o = Options();
  o.web_dir = (dir_ / "web-link").string();
  Start(o);
  auto res = Get("/js/app.js");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(res->body, "console.log('seamap');");
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
