// ResponseFramer: where one of httplib's answers ends, however its bytes arrive.
#include "server/http/response_framer.h"

#include <gtest/gtest.h>

namespace seamap::server {
namespace {

// Feeds `bytes` in pieces of `piece` bytes; returns how many were taken.
size_t FeedInPieces(ResponseFramer* f, const std::string& bytes, size_t piece) {
  size_t taken = 0;
  for (size_t at = 0; at < bytes.size() && !f->done() && !f->lost(); at += piece) {
    const std::string_view part = std::string_view(bytes).substr(at, piece);
    const size_t used = f->Feed(part);
    taken += used;
    if (used < part.size()) break;
  }
  return taken;
}

const std::string kJson =
    "HTTP/1.1 200 OK\r\nContent-Type: application/json\r\nContent-Length: 11\r\n\r\n{\"a\": true}";
const std::string kChunked =
    "HTTP/1.1 200 OK\r\nTransfer-Encoding: chunked\r\n\r\n5\r\nhello\r\n1a;ext=1\r\nabcdefghijklmnopqrstuvwxyz\r\n0\r\n"
    "X-Trailer: 1\r\n\r\n";

TEST(ResponseFramer, FindsTheEndHoweverTheBytesArrive) {
  const std::string next = "HTTP/1.1 204 No Content\r\n\r\n";
  for (const std::string& response : {kJson, kChunked, std::string("HTTP/1.1 204 No Content\r\nX: y\r\n\r\n"),
                                      std::string("HTTP/1.1 304 Not Modified\r\nETag: \"x\"\r\n\r\n"),
                                      std::string("HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\n\r\n")}) {
    for (size_t piece = 1; piece <= response.size() + next.size(); ++piece) {
      ResponseFramer f(false);
      EXPECT_EQ(FeedInPieces(&f, response + next, piece), response.size()) << piece << ": " << response;
      EXPECT_TRUE(f.done()) << piece;
      EXPECT_FALSE(f.close());
    }
  }
}

TEST(ResponseFramer, AHeadAnswerHasNoBody) {
  ResponseFramer f(true);
  const std::string head = kJson.substr(0, kJson.find("\r\n\r\n") + 4);
  EXPECT_EQ(f.Feed(head + "HTTP/1.1 200 OK\r\n"), head.size());
  EXPECT_TRUE(f.done());
}

TEST(ResponseFramer, AnEventStreamNeverEnds) {
  ResponseFramer f(false);
  const std::string head = "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\nTransfer-Encoding: chunked\r\n\r\n";
  EXPECT_EQ(f.Feed(head), head.size());
  for (int i = 0; i < 100; ++i) {
    const std::string event = "id: " + std::to_string(i) + "\nevent: tile\ndata: {}\n\n";
    char size[16];
    std::snprintf(size, sizeof size, "%zx\r\n", event.size());
    const std::string chunk = size + event + "\r\n";
    EXPECT_EQ(f.Feed(chunk), chunk.size());
    EXPECT_FALSE(f.done() || f.lost()) << i;
  }
  EXPECT_EQ(f.Feed("0\r\n\r\n"), 5u);
  EXPECT_TRUE(f.done());
}

TEST(ResponseFramer, InterimAnswersAreFollowedByTheRealOne) {
  ResponseFramer f(false);
  const std::string both = "HTTP/1.1 100 Continue\r\n\r\n" + kJson;
  EXPECT_EQ(f.Feed(both + "extra"), both.size());
  EXPECT_TRUE(f.done());
}

TEST(ResponseFramer, ConnectionCloseIsNoticed) {
  ResponseFramer f(false);
  f.Feed("HTTP/1.1 400 Bad Request\r\nConnection: Close\r\nContent-Length: 2\r\n\r\n{}");
  EXPECT_TRUE(f.done());
  EXPECT_TRUE(f.close());
}

TEST(ResponseFramer, WhatItCannotFollowIsLost) {
  for (const std::string bytes : {
           "HTTP/1.1 200 OK\r\nContent-Type: text/plain\r\n\r\nup to the close",  // no length
           "HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\n\r\n",
           "HTTP/1.1 200 OK\r\nContent-Length: ten\r\n\r\n",
           "HTTP/1.1 200 OK\r\nTransfer-Encoding: gzip\r\n\r\n",
           "HTTP/1.1 200 OK\r\nTransfer-Encoding: chunked\r\n\r\nzz\r\n",
           "HTTP/1.1 200 OK\r\nTransfer-Encoding: chunked\r\n\r\n2\r\nabXY",  // no CRLF after the data
           "SSH-2.0-OpenSSH\r\n\r\n",
           "HTTP/1.1 2x0 OK\r\n\r\n",
       }) {
    ResponseFramer f(false);
    EXPECT_EQ(f.Feed(bytes), bytes.size()) << bytes;
    EXPECT_TRUE(f.lost()) << bytes;
  }
  ResponseFramer huge(false);
  huge.Feed("HTTP/1.1 200 OK\r\n");
  for (int i = 0; i < 2000 && !huge.lost(); ++i) huge.Feed("X-Filler: " + std::string(40, 'f') + "\r\n");
  EXPECT_TRUE(huge.lost()) << "a head without end";
}

}  // namespace
}  // namespace seamap::server
