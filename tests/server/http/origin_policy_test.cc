// OriginPolicy: which browser pages may write, from Origin and Sec-Fetch-Site.
#include "server/http/origin_policy.h"

#include <gtest/gtest.h>

#include "core/util/error.h"

namespace seamap::server {
namespace {

TEST(NormalizeOrigin, SerialisesAsBrowsersDo) {
  EXPECT_EQ(NormalizeOrigin("http://127.0.0.1:8080"), "http://127.0.0.1:8080");
  EXPECT_EQ(NormalizeOrigin("HTTP://Ship.Example:80"), "http://ship.example");
  EXPECT_EQ(NormalizeOrigin("https://ship.example:443"), "https://ship.example");
  EXPECT_EQ(NormalizeOrigin("https://ship.example:8443"), "https://ship.example:8443");
  EXPECT_EQ(NormalizeOrigin("http://[::1]:3000"), "http://[::1]:3000");
  EXPECT_EQ(NormalizeOrigin("http://[::1]"), "http://[::1]");
  EXPECT_EQ(NormalizeOrigin("http://host:08080"), "http://host:8080");
  for (const char* bad : {"null", "", "127.0.0.1:8080", "http://", "http://host/", "http://host/path",
                          "http://user@host", "http://host:", "http://host:99999", "http://host:8080x", "://host",
                          "1http://host", "http://ho st", "http://[::1", "http://[zz]"})
    EXPECT_FALSE(NormalizeOrigin(bad)) << bad;
}

TEST(OriginPolicy, PagesOfTheServerItselfAndClientsThatAreNotBrowsersWrite) {
  const OriginPolicy policy;
  EXPECT_FALSE(policy.RefuseWrite("127.0.0.1:8080", "http://127.0.0.1:8080", "same-origin"));
  EXPECT_FALSE(policy.RefuseWrite("Ship.Example", "http://ship.example:80", std::nullopt));
  EXPECT_FALSE(policy.RefuseWrite("ship.example", "https://ship.example", std::nullopt)) << "behind a TLS proxy";
  EXPECT_FALSE(policy.RefuseWrite("127.0.0.1:8080", std::nullopt, std::nullopt)) << "curl";
  EXPECT_FALSE(policy.RefuseWrite("127.0.0.1:8080", std::nullopt, "same-origin")) << "a browser without Origin";
  EXPECT_FALSE(policy.RefuseWrite("127.0.0.1:8080", std::nullopt, "none")) << "typed by the browser's user";
}

TEST(OriginPolicy, PagesOfOtherSitesAreRefused) {
  const OriginPolicy policy;
  struct Case {
    const char* host;
    std::optional<std::string_view> origin, fetch_site;
    const char* what;
  };
  for (const Case& c : std::vector<Case>{
           {"127.0.0.1:8080", "http://evil.example", "cross-site", "another site"},
           {"127.0.0.1:8080", "http://127.0.0.1:8081", "same-site", "another port"},
           {"127.0.0.1:8080", "http://127.0.0.1", std::nullopt, "the default port"},
           {"127.0.0.1:8080", "null", "cross-site", "a sandboxed frame or a file: page"},
           {"127.0.0.1:8080", "garbage", std::nullopt, "not an origin"},
           {"", "http://127.0.0.1:8080", std::nullopt, "no Host to compare with"},
           {"127.0.0.1:8080", std::nullopt, "cross-site", "no Origin, but Sec-Fetch-Site"},
           {"127.0.0.1:8080", std::nullopt, "same-site", "a sibling subdomain"},
       }) {
    auto why = policy.RefuseWrite(c.host, c.origin, c.fetch_site);
    ASSERT_TRUE(why) << c.what;
    EXPECT_NE(why->find("cross-site write refused"), std::string::npos) << *why;
    EXPECT_NE(why->find("--allow-origin"), std::string::npos) << *why;
  }
}

TEST(OriginPolicy, AllowedOriginsWriteAndAreNamedForCors) {
  const OriginPolicy policy({"http://10.0.0.5:3000", "HTTPS://Dash.Example:443"});
  EXPECT_FALSE(policy.RefuseWrite("127.0.0.1:8080", "http://10.0.0.5:3000", "cross-site"));
  EXPECT_FALSE(policy.RefuseWrite("127.0.0.1:8080", "https://dash.example", "cross-site"));
  EXPECT_TRUE(policy.RefuseWrite("127.0.0.1:8080", "http://10.0.0.5:3001", "cross-site"));
  EXPECT_EQ(policy.Allowed("https://dash.example"), "https://dash.example");
  EXPECT_FALSE(policy.Allowed("http://dash.example"));
  EXPECT_FALSE(policy.Allowed("null"));
}

TEST(OriginPolicy, CheckNamesTheOptionAndTheExpectedForm) {
  EXPECT_NO_THROW(OriginPolicy::Check({"http://10.0.0.5:3000"}));
  for (const char* bad : {"10.0.0.5:3000", "http://host/", "*", "null"}) {
    try {
      OriginPolicy::Check({"http://ok.example", bad});
      ADD_FAILURE() << bad;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "--allow-origin");
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("scheme://host[:port]"), std::string::npos) << e.what();
    }
  }
}

TEST(OriginPolicy, SafeMethodsAreReads) {
  for (const char* m : {"GET", "HEAD", "OPTIONS"}) EXPECT_TRUE(OriginPolicy::IsSafeMethod(m)) << m;
  for (const char* m : {"POST", "PATCH", "DELETE", "PUT", "get", "TRACE"})
    EXPECT_FALSE(OriginPolicy::IsSafeMethod(m)) << m;
}

}  // namespace
}  // namespace seamap::server
