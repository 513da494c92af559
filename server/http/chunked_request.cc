#include "server/http/chunked_request.h"

#include <algorithm>

namespace seamap::server {
namespace {

constexpr size_t kMaxSizeLine = 4096;  // a chunk-size with its extensions

int HexValue(unsigned char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

size_t ChunkedRequestBody::Refuse(size_t used, int status, std::string error) {
  state_ = State::kRefused;
  status_ = status;
  error_ = std::move(error);
  return used;
}

size_t ChunkedRequestBody::Feed(std::string_view bytes) {
  size_t i = 0;
  while (i < bytes.size()) {
    const unsigned char c = static_cast<unsigned char>(bytes[i]);
    switch (state_) {
      case State::kSize:
        if (const int v = HexValue(c); v >= 0) {
          chunk_ = chunk_ * 16 + static_cast<size_t>(v);
          // Refused as soon as the size shows it: the data is never read.
          if (chunk_ > max_body_ - body_)
            return Refuse(i, 413, "the request body is over the limit of " + std::to_string(max_body_ / 1024) + " KiB");
          if (++line_ > kMaxSizeLine) return Refuse(i, 400, "a chunk size line over 4 KiB");
        } else if (line_ == 0) {
          return Refuse(i, 400, "a chunk does not start with its size in hex digits");
        } else if (c == ';') {
          state_ = State::kExtension;
        } else if (c == '\r') {
          state_ = State::kSizeLf;
        } else {
          return Refuse(i, 400, "a chunk size is followed by something other than ';' or CRLF");
        }
        break;
      case State::kExtension:  // httplib skips extensions; only their bytes are checked
        if (c == '\r') {
          state_ = State::kSizeLf;
        } else if ((c < 0x20 && c != '\t') || c == 0x7f) {
          return Refuse(i, 400, "a control character in a chunk extension");
        } else if (++line_ > kMaxSizeLine) {
          return Refuse(i, 400, "a chunk size line over 4 KiB");
        }
        break;
      case State::kSizeLf:
        if (c != '\n') return Refuse(i, 400, "a chunk size line does not end with CRLF");
        line_ = 0;
        state_ = chunk_ == 0 ? State::kEndCr : State::kData;
        break;
      case State::kData: {
        const size_t n = std::min(chunk_, bytes.size() - i);
        chunk_ -= n;
        body_ += n;
        i += n;
        if (chunk_ == 0) state_ = State::kDataCr;
        continue;
      }
      case State::kDataCr:
      case State::kDataLf:
        if (c != (state_ == State::kDataCr ? '\r' : '\n'))
          return Refuse(i, 400, "chunk data is not followed by CRLF (a wrong chunk size?)");
        state_ = state_ == State::kDataCr ? State::kDataLf : State::kSize;
        break;
      case State::kEndCr:
        if (c != '\r') return Refuse(i, 400, "trailer fields after a chunked body are not accepted");
        state_ = State::kEndLf;
        break;
      case State::kEndLf:
        if (c != '\n') return Refuse(i, 400, "the last chunk is not followed by CRLF");
        state_ = State::kDone;
        return i + 1;
      case State::kDone:
      case State::kRefused:
        return i;
    }
    ++i;
  }
  return i;
}

}  // namespace seamap::server
