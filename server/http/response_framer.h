#pragma once
// Where the backend's answer to one request ends. The tile front end relays
// requests to httplib one at a time (httplib 0.11 drops the bytes of a
// pipelined request that arrived with the one before), so it has to see each
// answer end before it sends the next request or answers a tile itself.
#include <cstddef>
#include <string>
#include <string_view>

namespace seamap::server {

class ResponseFramer {
 public:
  // `head_request`: the answer to a HEAD has no body, whatever its head says.
  explicit ResponseFramer(bool head_request) : head_request_(head_request) {}

  // Takes the next bytes the backend sent; returns how many of them belong to
  // this response (all of them until it is done).
  size_t Feed(std::string_view bytes);

  bool done() const { return state_ == State::kDone; }
  // The answer cannot be followed (a body up to the close, a protocol switch,
  // not HTTP): relay everything from now on, byte for byte.
  bool lost() const { return state_ == State::kLost; }
  // Nothing of the answer (past interim 1xx ones) has come yet.
  bool between_answers() const { return state_ == State::kHead && line_.empty(); }
  // The answer said "Connection: close": the backend closes after it.
  bool close() const { return close_; }

 private:
  enum class State { kHead, kBody, kChunkSize, kChunkData, kChunkEnd, kTrailer, kDone, kLost };
  void StartBody();
  // Appends to `line_` up to a LF; true once the line is complete.
  bool TakeLine(std::string_view bytes, size_t* used);

  bool head_request_;
  State state_ = State::kHead;
  std::string line_;      // the head, a chunk-size line or a trailer line, as it arrives
  size_t remaining_ = 0;  // of the body, a chunk, or a chunk's CRLF
  bool close_ = false;
};

}  // namespace seamap::server
