// A catalogue is the same server as one map's: it answers what a single map
// answers (JSON errors, the console's MIME types, listen errors, tiles the
// front end passes on) under /missions/{id}/.
#include "tests/server/http_test_fixture.h"

namespace seamap::server {
namespace {

using namespace http_test;

class HttpCatalogueTest : public HttpServerTest {
 protected:
  void StartCatalogue() {
    maps_ = test::WriteTestMission(dir_ / "maps");
    catalogue_ = std::make_unique<HttpServer>(Options(), (dir_ / "maps").string());
    catalogue_->Bind();
    catalogue_->Start();
    client_ = std::make_unique<httplib::Client>("127.0.0.1", catalogue_->port());
    client_->set_read_timeout(60);
  }
  void TearDown() override {
    if (catalogue_) catalogue_->Stop();
    HttpServerTest::TearDown();
  }
  test::TestMission maps_;
  std::unique_ptr<HttpServer> catalogue_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(HttpCatalogueTest, UnknownPathsGetAJsonError) {
  StartCatalogue();
  ExpectError(client_->Get("/no/such/file.txt"), 404, "not found", "an unknown file");
  ExpectError(client_->Get("/missions/nope/tiles.json"), 404, "no mission 'nope'", "an unknown mission");
  ExpectError(client_->Get("/api/status"), 404, "no such API in a catalogue", "the root's API");
  ExpectError(client_->Get("/missions/mission/api/nothing"), 404, "no such API endpoint", "an unknown endpoint");
}

TEST_F(HttpCatalogueTest, TheConsolesModulesAndIconsHaveTheirTypes) {
  seamap::testing::WriteFile(web_ / "js" / "map.mjs", "export const x = 1;");
  seamap::testing::WriteFile(web_ / "icon.svg", "<svg xmlns='http://www.w3.org/2000/svg'/>");
  StartCatalogue();
  auto mjs = client_->Get("/js/map.mjs");
  ASSERT_TRUE(mjs);
  EXPECT_EQ(mjs->status, 200);
  EXPECT_EQ(mjs->get_header_value("Content-Type"), "text/javascript");
  auto svg = client_->Get("/icon.svg");
  ASSERT_TRUE(svg);
  EXPECT_EQ(svg->get_header_value("Content-Type"), "image/svg+xml");
  auto root = client_->Get("/");
  ASSERT_TRUE(root);
  EXPECT_EQ(root->status, 302);
  EXPECT_EQ(root->get_header_value("Location"), "/missions.html");
}

TEST_F(HttpCatalogueTest, TilesTheFrontEndPassesOnAreTheSameBytesWithOneCorsHeader) {
  StartCatalogue();
  const auto& [id, bytes] = *maps_.tiles.begin();
  const std::string zxy = std::to_string(id.z) + "/" + std::to_string(id.x) + "/" + std::to_string(id.y) + ".png";
  auto plain = client_->Get(("/missions/mission/tiles/" + zxy).c_str());
  auto escaped = client_->Get(("/missions/mission/tiles/%3" + zxy.substr(0, 1) + zxy.substr(1)).c_str());
  for (const auto& res : {&plain, &escaped}) {
    ASSERT_TRUE(*res);
    EXPECT_EQ((*res)->status, 200);
    EXPECT_EQ((*res)->body, Text(bytes));
    EXPECT_EQ((*res)->get_header_value_count("Access-Control-Allow-Origin"), 1u);
  }
  auto tilejson = client_->Get("/missions/mission/tiles.json");
  ASSERT_TRUE(tilejson);
  EXPECT_EQ(tilejson->get_header_value_count("Access-Control-Allow-Origin"), 1u);
  const json j = json::parse(tilejson->body);
  EXPECT_NE(j["tiles"][0].get<std::string>().find("/missions/mission/tiles/{z}/{x}/{y}.png"), std::string::npos);
  EXPECT_EQ(j["seamap_formats"][0], "png");
}

TEST_F(HttpCatalogueTest, BindingATakenPortNamesTheOption) {
  StartCatalogue();
  ServerOptions o = Options();
  o.port = catalogue_->port();
  HttpServer second(o, (dir_ / "maps").string());
  try {
    second.Bind();
    FAIL() << "bound a port already in use";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--port");
  }
}

}  // namespace
}  // namespace seamap::server
