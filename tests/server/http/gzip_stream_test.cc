// The event stream's gzip: every piece decodable as soon as it is written.
#include "server/http/gzip_stream.h"

#include <zlib.h>

#include <gtest/gtest.h>

namespace seamap::server {
namespace {

// Inflates what has arrived so far (a gzip stream, maybe unfinished).
class Inflater {
 public:
  Inflater() { EXPECT_EQ(inflateInit2(&z_, 15 + 16), Z_OK); }
  ~Inflater() { inflateEnd(&z_); }
  std::string Feed(const std::string& in) {
    std::string out;
    z_.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
    z_.avail_in = static_cast<uInt>(in.size());
    char buffer[4096];
    while (z_.avail_in > 0 || z_.avail_out == 0) {
      z_.next_out = reinterpret_cast<Bytef*>(buffer);
      z_.avail_out = sizeof buffer;
      const int rc = inflate(&z_, Z_SYNC_FLUSH);
      out.append(buffer, sizeof buffer - z_.avail_out);
      if (rc == Z_STREAM_END) ended_ = true;
      if (rc != Z_OK || rc == Z_STREAM_END) break;
    }
    return out;
  }
  bool ended() const { return ended_; }

 private:
  z_stream z_{};
  bool ended_ = false;
};

TEST(GzipStream, EachPieceDecodesAsSoonAsItIsWrittenAndRepeatsCostLittle) {
  GzipStream gzip;
  Inflater inflater;
  const std::string event = "id: 1\nevent: tile\ndata: {\"layer\":\"\",\"z\":19,\"x\":270001,\"y\":190001}\n\n";
  size_t packed_total = 0;
  for (int i = 0; i < 50; ++i) {
    const std::string packed = gzip.Write(event);
    packed_total += packed.size();
    EXPECT_EQ(inflater.Feed(packed), event) << "piece " << i << " held back";
  }
  EXPECT_LT(packed_total, 50 * event.size() / 4) << "the repeated text must compress";
  inflater.Feed(gzip.Finish());
  EXPECT_TRUE(inflater.ended());
  EXPECT_EQ(gzip.Finish(), "");
  EXPECT_THROW(gzip.Write("late"), std::logic_error);
}

TEST(GzipStream, AcceptEncodingIsReadWithItsWeights) {
  EXPECT_TRUE(AcceptsGzip("gzip, deflate, br"));
  EXPECT_TRUE(AcceptsGzip("deflate, GZIP;q=0.5"));
  EXPECT_TRUE(AcceptsGzip("x-gzip"));
  EXPECT_FALSE(AcceptsGzip(""));
  EXPECT_FALSE(AcceptsGzip("identity"));
  EXPECT_FALSE(AcceptsGzip("gzip;q=0"));
  EXPECT_FALSE(AcceptsGzip("gzip;q=0.000, br"));
  EXPECT_FALSE(AcceptsGzip("gzipped"));
}

}  // namespace
}  // namespace seamap::server
