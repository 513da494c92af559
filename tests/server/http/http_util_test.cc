#include "server/http/http_util.h"

#include <gtest/gtest.h>

namespace seamap::server {
namespace {

TEST(HttpUtil, ParseIdTakesNonNegativeIntegersOnly) {
  EXPECT_EQ(ParseId("42", "frame id"), 42);
  for (const char* bad : {"-1", "4x", "", "1.5", "99999999999999999999"}) {
    try {
      ParseId(bad, "frame id");
      ADD_FAILURE() << bad;
    } catch (const ApiError& e) {
      EXPECT_EQ(e.status(), 400);
      EXPECT_NE(std::string(e.what()).find("frame id"), std::string::npos) << e.what();
    }
  }
}

TEST(HttpUtil, AuthorizedNeedsTheExactBearerToken) {
  httplib::Request req;
  EXPECT_TRUE(Authorized(req, ""));  // no token: everyone
  EXPECT_FALSE(Authorized(req, "s3cret"));
  req.set_header("Authorization", "Bearer s3cret");
  EXPECT_TRUE(Authorized(req, "s3cret"));
  EXPECT_FALSE(Authorized(req, "s3cre"));
}

TEST(HttpUtil, BodiesAndAnswers) {
  httplib::Request req;
  req.body = R"({"a": 1})";
  EXPECT_EQ(ParseBody(req)["a"], 1);
  req.body = "{\"a\": \"\xff\"}";
  try {
    ParseBody(req);
    ADD_FAILURE();
  } catch (const ApiError& e) {
    EXPECT_NE(std::string(e.what()).find("0xFF"), std::string::npos) << e.what();
  }
  httplib::Response res;
  SendError(res, 404, "no \xff here");  // quoted client bytes: replaced, never a throw
  EXPECT_EQ(res.status, 404);
  EXPECT_NE(res.body.find("\"error\""), std::string::npos);
}

}  // namespace
}  // namespace seamap::server
