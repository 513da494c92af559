// ChunkedRequestBody: where a client's chunked body ends, what it decodes
// to, and what is refused (400 malformed, 413 over the limit) as soon as the
// bytes show it.
#include "server/http/chunked_request.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace seamap::server {
namespace {

constexpr size_t kLimit = 64 * 1024;

// Feeds `bytes` in pieces of `step` and reports how many were taken.
size_t FeedInPieces(ChunkedRequestBody* body, const std::string& bytes, size_t step) {
  size_t taken = 0;
  for (size_t at = 0; at < bytes.size() && !body->done() && !body->refused(); at += step) {
    const std::string_view piece = std::string_view(bytes).substr(at, step);
    const size_t used = body->Feed(piece);
    taken += used;
    if (used < piece.size()) break;
  }
  return taken;
}

std::string Chunk(const std::string& data) {
  char size[16];
  std::snprintf(size, sizeof size, "%zx", data.size());
  return std::string(size) + "\r\n" + data + "\r\n";
}

TEST(ChunkedRequestBody, FindsTheEndHoweverTheBytesArrive) {
  const std::string body = Chunk("{\"a\":") + "3;name=value\r\n1}\n\r\n" + Chunk(std::string(300, 'x')) + "0\r\n\r\n";
  const std::string next = "GET /tiles/3/4/2.png HTTP/1.1\r\n\r\n";
  for (size_t step : {size_t{1}, size_t{2}, size_t{7}, body.size(), body.size() + next.size()}) {
    ChunkedRequestBody b(kLimit);
    EXPECT_EQ(FeedInPieces(&b, body + next, step), body.size()) << "step " << step;
    EXPECT_TRUE(b.done()) << "step " << step;
    EXPECT_EQ(b.body_bytes(), 5u + 3u + 300u);
  }
  ChunkedRequestBody upper(kLimit);
  EXPECT_EQ(upper.Feed("A\r\n0123456789\r\n0\r\n\r\n"), 20u);
  EXPECT_TRUE(upper.done());
  ChunkedRequestBody empty(kLimit);
  EXPECT_EQ(empty.Feed("0\r\n\r\n"), 5u);
  EXPECT_TRUE(empty.done());
  ChunkedRequestBody partial(kLimit);
  EXPECT_EQ(partial.Feed("5\r\nab"), 5u);
  EXPECT_FALSE(partial.done() || partial.refused()) << "waits for more";
}

TEST(ChunkedRequestBody, TheLimitHoldsAsSoonAsASizeShowsIt) {
  ChunkedRequestBody exact(kLimit);
  EXPECT_EQ(FeedInPieces(&exact, Chunk(std::string(kLimit, 'x')) + "0\r\n\r\n", 4096), kLimit + 14);
  EXPECT_TRUE(exact.done()) << "exactly the limit is fine";

  ChunkedRequestBody one_chunk(kLimit);
  const size_t used = one_chunk.Feed("10001\r\n");
  EXPECT_TRUE(one_chunk.refused());
  EXPECT_EQ(one_chunk.status(), 413);
  EXPECT_EQ(used, 4u) << "refused at the digit that passed the limit";
  EXPECT_NE(one_chunk.error().find("64 KiB"), std::string::npos) << one_chunk.error();

  // Many small chunks add up.
  ChunkedRequestBody many(kLimit);
  std::string stream;
  for (int i = 0; i < 70; ++i) stream += Chunk(std::string(1024, 'y'));
  FeedInPieces(&many, stream, 1000);
  EXPECT_TRUE(many.refused());
  EXPECT_EQ(many.status(), 413);
  EXPECT_LE(many.body_bytes(), kLimit);

  ChunkedRequestBody huge(kLimit);
  huge.Feed("ffffffffffffffffffffffffffffffff\r\n");  // no overflow back under the limit
  EXPECT_EQ(huge.status(), 413);
}

TEST(ChunkedRequestBody, WhatHttplibWouldReadDifferentlyIs400) {
  for (const std::string bad : {
           "\r\n",                           // no size
           "x\r\n",                          // not hex
           " 5\r\nhello\r\n0\r\n\r\n",       // leading space (strtoul skips it)
           "+5\r\nhello\r\n0\r\n\r\n",       // a sign
           "0x5\r\nhello\r\n0\r\n\r\n",      // strtoul reads the 0x prefix
           "5 \r\nhello\r\n0\r\n\r\n",       // trailing space
           "5\nhello\r\n0\r\n\r\n",          // bare LF
           "5\rhello\r\n0\r\n\r\n",          // bare CR
           "5\r\nhelloX\r\n0\r\n\r\n",       // data longer than its size
           "5\r\nhello\n0\r\n\r\n",          // no CR after the data
           "5;a\x01\r\nhello\r\n0\r\n\r\n",  // a control character in an extension
           "0\r\nTrailer: x\r\n\r\n",        // trailer fields: httplib takes none
           "0\r\n\n",
       }) {
    ChunkedRequestBody b(kLimit);
    FeedInPieces(&b, bad, 1);
    EXPECT_TRUE(b.refused()) << bad;
    EXPECT_EQ(b.status(), 400) << bad;
    EXPECT_FALSE(b.error().empty());
  }
  ChunkedRequestBody long_line(kLimit);
  long_line.Feed("5;" + std::string(5000, 'e'));
  EXPECT_TRUE(long_line.refused()) << "an endless extension is not buffered";
  ChunkedRequestBody zeros(kLimit);
  zeros.Feed(std::string(5000, '0'));
  EXPECT_TRUE(zeros.refused()) << "nor endless leading zeros";
  ChunkedRequestBody after(kLimit);
  after.Feed("x");
  EXPECT_EQ(after.Feed("0\r\n\r\n"), 0u) << "nothing is taken once refused";
}

}  // namespace
}  // namespace seamap::server
