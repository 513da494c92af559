#pragma once
// A raw HTTP client for the front end's tests: a socket that sends bytes
// exactly as given (in pieces, pipelined, malformed), and a strict parser of
// what comes back, so a test can tell a well-formed response from garbage.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace seamap::server::raw_http {

struct Response {
  int status = 0;
  std::vector<std::pair<std::string, std::string>> headers;
  std::string body;

  std::string Header(std::string_view name) const {
    for (const auto& [n, v] : headers)
      if (n.size() == name.size() && std::equal(n.begin(), n.end(), name.begin(), [](char a, char b) {
            return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
          }))
        return v;
    return "";
  }
};

enum class Parsed { kIncomplete, kOk, kMalformed };

// One response at the start of `data`: "HTTP/1.x DDD reason", header fields,
// then a body by Content-Length, by chunks, or (with neither) up to `at_eof`.
// 1xx, 204, 304 and answers to HEAD have no body.
inline Parsed ParseResponse(std::string_view data, bool head_request, bool at_eof, Response* out, size_t* used) {
  const size_t head_end = data.find("\r\n\r\n");
  const size_t line_end = data.find("\r\n");
  const bool status_line_possible = std::string_view("HTTP/1.").substr(0, std::min<size_t>(data.size(), 7)) ==
                                    data.substr(0, std::min<size_t>(data.size(), 7));
  if (!status_line_possible) return Parsed::kMalformed;
  if (head_end == std::string_view::npos)
    return at_eof || data.size() > 65536 ? Parsed::kMalformed : Parsed::kIncomplete;
  const std::string_view line = data.substr(0, line_end);
  if (line.size() < 13 || (line[7] != '0' && line[7] != '1') || line[8] != ' ' || line[12] != ' ' ||
      !std::isdigit(static_cast<unsigned char>(line[9])) || !std::isdigit(static_cast<unsigned char>(line[10])) ||
      !std::isdigit(static_cast<unsigned char>(line[11])))
    return Parsed::kMalformed;
  Response r;
  r.status = std::stoi(std::string(line.substr(9, 3)));
  size_t pos = line_end + 2;
  while (pos < head_end + 2) {
    const size_t end = data.find("\r\n", pos);
    const std::string_view field = data.substr(pos, end - pos);
    const size_t colon = field.find(':');
    if (colon == std::string_view::npos || colon == 0) return Parsed::kMalformed;
    for (char c : field.substr(0, colon))
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') return Parsed::kMalformed;
    std::string_view value = field.substr(colon + 1);
    while (!value.empty() && value.front() == ' ') value.remove_prefix(1);
    r.headers.emplace_back(std::string(field.substr(0, colon)), std::string(value));
    pos = end + 2;
  }
  pos = head_end + 4;
  const std::string length = r.Header("Content-Length");
  if (head_request || r.status < 200 || r.status == 204 || r.status == 304) {
  } else if (r.Header("Transfer-Encoding") == "chunked") {
    while (true) {
      const size_t size_end = data.find("\r\n", pos);
      if (size_end == std::string_view::npos) return at_eof ? Parsed::kMalformed : Parsed::kIncomplete;
      size_t size = 0;
      try {
        size = std::stoul(std::string(data.substr(pos, size_end - pos)), nullptr, 16);
      } catch (const std::exception&) {
        return Parsed::kMalformed;
      }
      if (data.size() < size_end + 2 + size + 2) return at_eof ? Parsed::kMalformed : Parsed::kIncomplete;
      if (data.substr(size_end + 2 + size, 2) != "\r\n") return Parsed::kMalformed;
      r.body.append(data.substr(size_end + 2, size));
      pos = size_end + 2 + size + 2;
      if (size == 0) break;  // (no trailers from these servers)
    }
  } else if (!length.empty()) {
    if (length.find_first_not_of("0123456789") != std::string::npos) return Parsed::kMalformed;
    const size_t n = std::stoul(length);
    if (data.size() < pos + n) return at_eof ? Parsed::kMalformed : Parsed::kIncomplete;
    r.body = std::string(data.substr(pos, n));
    pos += n;
  } else {
    if (!at_eof) return Parsed::kIncomplete;
    r.body = std::string(data.substr(pos));
    pos = data.size();
  }
  *out = std::move(r);
  *used = pos;
  return Parsed::kOk;
}

// A client connection to 127.0.0.1:port. Every read waits at most `patience`
// seconds: a server that neither answers nor closes fails the test, never hangs it.
class Connection {
 public:
  explicit Connection(int port, int patience_s = 30, int receive_buffer = 0) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    if (receive_buffer > 0) ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof receive_buffer);
    int one = 1;
    ::setsockopt(fd_, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    timeval timeout{patience_s, 0};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<uint16_t>(port));
    ::inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
  }
  ~Connection() {
    if (fd_ >= 0) ::close(fd_);
  }
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  bool connected() const { return connected_; }

  // False when the server closed the connection first (or it never opened).
  bool Send(std::string_view bytes) {
    while (!bytes.empty()) {
      const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
      if (n <= 0) return false;
      bytes.remove_prefix(static_cast<size_t>(n));
    }
    return connected_;
  }
  void ShutdownWrite() { ::shutdown(fd_, SHUT_WR); }

  // The next response; nullopt when the connection closed (or timed out)
  // first, or the bytes are not HTTP (`malformed()` then says so).
  std::optional<Response> Next(bool head_request = false) {
    while (true) {
      if (buffer_.empty() && eof_) return std::nullopt;
      Response r;
      size_t used = 0;
      const Parsed p = ParseResponse(buffer_, head_request, eof_, &r, &used);
      if (p == Parsed::kOk) {
        buffer_.erase(0, used);
        return r;
      }
      if (p == Parsed::kMalformed) {
        malformed_ = true;
        return std::nullopt;
      }
      if (!Receive() && !eof_) return std::nullopt;  // timed out
    }
  }

  // Reads until the server closes; false if it did not within the patience.
  bool ReadToEnd() {
    while (!eof_)
      if (!Receive()) return eof_;
    return true;
  }
  // Takes what has arrived (for a caller that polls `fd()`).
  void ReceiveSome() { Receive(); }
  int fd() const { return fd_; }
  // The unparsed bytes received so far.
  const std::string& buffer() const { return buffer_; }
  bool closed() const { return eof_; }
  bool timed_out() const { return timed_out_; }
  bool malformed() const { return malformed_; }

 private:
  // Appends what arrives; false on close, error or timeout.
  bool Receive() {
    char chunk[16384];
    const ssize_t n = ::recv(fd_, chunk, sizeof chunk, 0);
    if (n > 0) {
      buffer_.append(chunk, static_cast<size_t>(n));
      return true;
    }
    if (n == 0 || errno == ECONNRESET) eof_ = true;
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) timed_out_ = true;
    return false;
  }

  int fd_ = -1;
  bool connected_ = false;
  std::string buffer_;
  bool eof_ = false, timed_out_ = false, malformed_ = false;
};

}  // namespace seamap::server::raw_http
