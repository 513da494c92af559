#pragma once
// Where a client's chunked request body (RFC 9112 section 7.1) ends, read
// strictly and against the body limit. The tile front end relays such a
// body to httplib as it arrives: it must know where the body ends (the next
// request starts there, and httplib must see the same end), and stop one
// that outgrows the limit before httplib has buffered it whole (httplib 0.11
// has no limit for chunked bodies).
#include <cstddef>
#include <string>
#include <string_view>

namespace seamap::server {

class ChunkedRequestBody {
 public:
  explicit ChunkedRequestBody(size_t max_body_bytes) : max_body_(max_body_bytes) {}

  // Takes the next bytes after the request head; returns how many of them
  // belong to the body (fewer once it is done or refused).
  size_t Feed(std::string_view bytes);

  bool done() const { return state_ == State::kDone; }
  // The body is over the limit (413) or not chunked as httplib reads it
  // (400): answer status() with error() and close the connection.
  bool refused() const { return state_ == State::kRefused; }
  int status() const { return status_; }
  const std::string& error() const { return error_; }
  // Decoded bytes so far (chunk data without framing).
  size_t body_bytes() const { return body_; }

 private:
  // kSize: chunk-size digits; kExtension: ";..." up to CR; kSizeLf: the LF
  // after it; kData, kDataCr, kDataLf: chunk data and its CRLF; kEndLf: the
  // CRLF after the last chunk (no trailer fields: httplib takes none).
  enum class State { kSize, kExtension, kSizeLf, kData, kDataCr, kDataLf, kEndCr, kEndLf, kDone, kRefused };
  size_t Refuse(size_t used, int status, std::string error);

  size_t max_body_;
  State state_ = State::kSize;
  size_t line_ = 0;   // bytes of the chunk-size line so far
  size_t chunk_ = 0;  // the chunk-size, then the data still to come
  size_t body_ = 0;
  int status_ = 400;
  std::string error_;
};

}  // namespace seamap::server
