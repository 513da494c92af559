#include "server/http/response_framer.h"

#include <algorithm>
#include <cctype>
#include <optional>

#include "server/http/http_tokens.h"

namespace seamap::server {
namespace {

constexpr size_t kMaxHead = 64 * 1024;
constexpr size_t kMaxLine = 4096;

}  // namespace

bool ResponseFramer::TakeLine(std::string_view bytes, size_t* used) {
  const size_t lf = bytes.find('\n');
  const size_t n = lf == std::string_view::npos ? bytes.size() : lf + 1;
  line_.append(bytes.substr(0, n));
  *used = n;
  return lf != std::string_view::npos;
}

// The head is in line_: status line and fields, up to the blank line.
void ResponseFramer::StartBody() {
  const std::string head = std::move(line_);
  line_.clear();
  if (head.size() < 12 || head.compare(0, 7, "HTTP/1.") != 0 || head[8] != ' ' ||
      !std::all_of(head.begin() + 9, head.begin() + 12, [](unsigned char c) { return std::isdigit(c); })) {
    state_ = State::kLost;
    return;
  }
  const int status = std::stoi(head.substr(9, 3));
  bool chunked = false, other_coding = false;
  std::optional<size_t> length;
  size_t pos = head.find('\n') + 1;
  while (pos < head.size()) {
    const size_t end = head.find('\n', pos);
    std::string_view field = std::string_view(head).substr(pos, end - pos);
    if (!field.empty() && field.back() == '\r') field.remove_suffix(1);
    pos = end + 1;
    const size_t colon = field.find(':');
    if (colon == std::string_view::npos) continue;  // the blank line
    const std::string_view name = field.substr(0, colon), value = TrimSpace(field.substr(colon + 1));
    if (IEquals(name, "content-length")) {
      if (value.empty() || value.size() > 15 || value.find_first_not_of("0123456789") != std::string_view::npos) {
        state_ = State::kLost;
        return;
      }
      length = std::stoull(std::string(value));
    } else if (IEquals(name, "transfer-encoding")) {
      chunked = HasToken(value, "chunked");
      other_coding = !chunked;
    } else if (IEquals(name, "connection")) {
      close_ = close_ || HasToken(value, "close");
    }
  }
  if (status == 101) {
    state_ = State::kLost;  // another protocol from here on
  } else if (status >= 100 && status < 200) {
    state_ = State::kHead;  // 100 Continue: the real answer follows
    close_ = false;
  } else if (head_request_ || status == 204 || status == 304) {
    state_ = State::kDone;
  } else if (chunked) {
    state_ = State::kChunkSize;
  } else if (length && !other_coding) {
    remaining_ = *length;
    state_ = remaining_ == 0 ? State::kDone : State::kBody;
  } else {
    state_ = State::kLost;  // a body that ends when the connection does
  }
}

size_t ResponseFramer::Feed(std::string_view bytes) {
  size_t taken = 0;
  while (taken < bytes.size() && state_ != State::kDone && state_ != State::kLost) {
    const std::string_view rest = bytes.substr(taken);
    size_t used = 0;
    switch (state_) {
      case State::kHead: {
        // The head ends with an empty line (CRLF, or a bare LF).
        if (TakeLine(rest, &used)) {
          const std::string_view h = line_;
          const bool blank = (h.size() >= 3 && h.substr(h.size() - 3) == "\n\r\n") ||
                             (h.size() >= 2 && h.substr(h.size() - 2) == "\n\n");
          if (blank) StartBody();
        }
        if (state_ == State::kHead && line_.size() > kMaxHead) state_ = State::kLost;
        break;
      }
      case State::kBody:
        used = std::min(remaining_, rest.size());
        remaining_ -= used;
        if (remaining_ == 0) state_ = State::kDone;
        break;
      case State::kChunkSize:
      case State::kTrailer: {
        const bool line_done = TakeLine(rest, &used);
        if (line_.size() > kMaxLine) {
          state_ = State::kLost;
        } else if (line_done) {
          const std::string line = std::move(line_);
          line_.clear();
          if (state_ == State::kTrailer) {
            if (line == "\r\n" || line == "\n") state_ = State::kDone;
          } else {
            const std::string_view digits = TrimSpace(std::string_view(line).substr(0, line.find_first_of(";\r\n")));
            if (digits.empty() || digits.size() > 15 ||
                digits.find_first_not_of("0123456789abcdefABCDEF") != std::string_view::npos) {
              state_ = State::kLost;
            } else {
              remaining_ = std::stoull(std::string(digits), nullptr, 16);
              state_ = remaining_ == 0 ? State::kTrailer : State::kChunkData;
            }
          }
        }
        break;
      }
      case State::kChunkData:
        used = std::min(remaining_, rest.size());
        remaining_ -= used;
        if (remaining_ == 0) {
          state_ = State::kChunkEnd;
          remaining_ = 2;
        }
        break;
      case State::kChunkEnd:
        used = 1;
        if (rest[0] != (remaining_ == 2 ? '\r' : '\n'))
          state_ = State::kLost;
        else if (--remaining_ == 0)
          state_ = State::kChunkSize;
        break;
      default:
        break;
    }
    taken += used;
  }
  return state_ == State::kLost ? bytes.size() : taken;
}

}  // namespace seamap::server
