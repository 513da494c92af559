// ServerOptions: the config file's "server" object and Check(), each naming
// the bad key or option.
#include "server/server_options.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/util/error.h"
#include "tests/testing/temp_dir.h"

namespace seamap::server {
namespace {

using nlohmann::json;

TEST(ServerOptions, ReadsTheServerObjectOverTheDefaults) {
  ServerOptions o = ServerOptions::FromJson(
      json::parse(R"({"host": "127.0.0.1", "port": 9000, "token": "t", "threads": 8, "max_streams": 4})"), "cfg.json");
  EXPECT_EQ(o.host, "127.0.0.1");
  EXPECT_EQ(o.port, 9000);
  EXPECT_EQ(o.token, "t");
  EXPECT_EQ(o.threads, 8);
  EXPECT_EQ(o.max_streams, 4);
  o = ServerOptions::FromJson(json::parse(R"({"port": 0})"), "cfg.json");
  EXPECT_EQ(o.port, 0);
  EXPECT_EQ(o.host, ServerOptions{}.host);
  EXPECT_EQ(o.threads, ServerOptions{}.threads);
  EXPECT_NO_THROW(ServerOptions::FromJson(json::object(), "cfg.json").Check());
  o = ServerOptions::FromJson(json::parse(R"({"allow_origins": ["http://10.0.0.5:3000", "https://a.example"]})"),
                              "cfg.json");
  EXPECT_EQ(o.allow_origins, (std::vector<std::string>{"http://10.0.0.5:3000", "https://a.example"}));
}

TEST(ServerOptions, BadKeysAreNamedWithTheFile) {
  struct Case {
    std::string text, field, message;
  };
  for (const Case& c : std::vector<Case>{
           {R"({"port": 70000})", "server.port",
            "cfg.json: field 'server.port': expected a port number 0..65535, got 70000"},
           {R"({"port": -1})", "server.port", "expected a port number 0..65535, got -1"},
           {R"({"port": "80"})", "server.port", "expected a whole number, got \"80\""},
           {R"({"port": 80.5})", "server.port", "expected a whole number, got 80.5"},
           {R"({"port": 99999999999})", "server.port", "got 99999999999"},
           {R"({"threads": 1})", "server.threads", "expected 2..1024, got 1"},
           {R"({"max_streams": 0})", "server.max_streams", "expected 1..1024, got 0"},
           {R"({"host": 5})", "server.host", "expected a string, got 5"},
           {R"({"host": ""})", "server.host", "expected an address"},
           {R"({"token": null})", "server.token", "expected a string, got null"},
           {R"({"tokn": "x"})", "server.tokn",
            "unknown key (known: host, port, token, threads, max_streams, allow_origins)"},
           {R"({"allow_origins": "http://a.example"})", "server.allow_origins", "expected an array of origins"},
           {R"({"allow_origins": [3]})", "server.allow_origins", "expected origin strings, got 3"},
           {R"({"allow_origins": ["http://a.example/x"]})", "server.allow_origins",
            "expected an origin: scheme://host[:port] with no path"},
           {R"([1])", "server", "expected an object, got [1]"},
       }) {
    try {
      ServerOptions::FromJson(json::parse(c.text), "cfg.json");
      ADD_FAILURE() << "accepted " << c.text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), "cfg.json") << c.text;
      EXPECT_EQ(e.field(), c.field) << c.text;
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << c.text << ": " << e.what();
    }
  }
}

TEST(ServerOptions, CheckNamesTheCommandLineOption) {
  seamap::testing::TempDir dir;
  auto expect_error = [](const ServerOptions& o, const std::string& option, const std::string& message) {
    try {
      o.Check();
      ADD_FAILURE() << option << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), option) << e.what();
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  ServerOptions o;
  o.port = 70000;
  expect_error(o, "--port", "--port: expected a port number 0..65535, got 70000");
  o = {};
  o.threads = 1;
  expect_error(o, "--threads", "expected 2..1024, got 1");
  o = {};
  o.max_streams = 2000;
  expect_error(o, "--max-streams", "expected 1..1024, got 2000");
  o = {};
  o.host = "";
  expect_error(o, "--host", "expected an address");
  o = {};
  o.allow_origins = {"10.0.0.5:3000"};
  expect_error(o, "--allow-origin", "expected an origin: scheme://host[:port]");
  o = {};
  o.web_dir = dir.path().string();
  expect_error(o, "--web", "has no index.html");
  seamap::testing::WriteFile(dir / "index.html", "<!doctype html>");
  EXPECT_NO_THROW(o.Check());
}

}  // namespace
}  // namespace seamap::server
