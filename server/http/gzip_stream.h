#pragma once
// A gzip stream written piece by piece, each piece flushed (Z_SYNC_FLUSH) so
// the receiver can decode it at once: live events compressed on the wire
// without holding them back. One dictionary for the whole stream, so the
// repeated field names of the events cost almost nothing after the first.
#include <memory>
#include <string>
#include <string_view>

namespace seamap::server {

class GzipStream {
 public:
  GzipStream();
  ~GzipStream();
  GzipStream(const GzipStream&) = delete;
  GzipStream& operator=(const GzipStream&) = delete;

  // The compressed bytes of `piece` (the gzip header with the first one).
  std::string Write(std::string_view piece);
  // The stream's end (trailer with CRC and length).
  std::string Finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Does an Accept-Encoding header accept gzip (and not with q=0)?
bool AcceptsGzip(std::string_view accept_encoding);

}  // namespace seamap::server
