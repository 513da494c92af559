#include "server/http/tile_front_end.h"

#include <arpa/inet.h>
#include <event2/buffer.h>
#include <event2/bufferevent.h>
#include <event2/event.h>
#include <event2/listener.h>
#include <event2/thread.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <vector>

#include "core/util/error.h"
#include "server/http/chunked_request.h"
#include "server/http/request_head.h"
#include "server/http/response_framer.h"
#include "server/tile_answer.h"

namespace seamap::server {
namespace {

constexpr RequestHeadLimits kLimits;
// Reading one side stops while this much waits to be written to the other
// (a client that does not read its answers is not read either).
constexpr size_t kMaxQueuedBytes = 4 << 20;

const char* Reason(int status) {
  switch (status) {
    case 200:
      return "OK";
    case 204:
      return "No Content";
    case 304:
      return "Not Modified";
    case 400:
      return "Bad Request";
    case 404:
      return "Not Found";
    case 411:
      return "Length Required";
    case 413:
      return "Content Too Large";
    case 414:
      return "URI Too Long";
    case 431:
      return "Request Header Fields Too Large";
    case 501:
      return "Not Implemented";
    case 505:
      return "HTTP Version Not Supported";
    default:
      return "Internal Server Error";
  }
}

// The verdict on the next request in `in`; the bytes are made contiguous
// only when the head spans the buffer's chunks.
RequestHead NextHead(evbuffer* in) {
  // RFC 9112 lets a client send empty lines between requests.
  char start[2];
  while (evbuffer_copyout(in, start, 2) == 2 && start[0] == '\r' && start[1] == '\n') evbuffer_drain(in, 2);
  evbuffer_iovec first;
  if (evbuffer_peek(in, -1, nullptr, &first, 1) < 1) return {};
  RequestHead h = ParseRequestHead({static_cast<const char*>(first.iov_base), first.iov_len}, kLimits);
  const size_t length = evbuffer_get_length(in);
  if (h.kind != RequestHead::Kind::kNeedMore || first.iov_len >= length) return h;
  const size_t n = std::min(length, kLimits.max_head_bytes);
  return ParseRequestHead({reinterpret_cast<const char*>(evbuffer_pullup(in, static_cast<ev_ssize_t>(n))), n}, kLimits);
}

bool Ended(const ResponseFramer& f) {
  return f.done() || f.lost();
}
bool Ended(const ChunkedRequestBody& b) {
  return b.done() || b.refused();
}

// How many bytes at the start of `in` belong to the response or the chunked
// request body `framer` follows.
template <typename Framer>
size_t Frame(evbuffer* in, Framer* framer) {
  const int chunks = evbuffer_peek(in, -1, nullptr, nullptr, 0);
  std::vector<evbuffer_iovec> v(static_cast<size_t>(std::max(chunks, 0)));
  evbuffer_peek(in, -1, nullptr, v.data(), chunks);
  size_t taken = 0;
  for (const evbuffer_iovec& chunk : v) {
    const size_t used = framer->Feed({static_cast<const char*>(chunk.iov_base), chunk.iov_len});
    taken += used;
    if (used < chunk.iov_len || Ended(*framer)) break;
  }
  return taken;
}

void FreeBody(const void*, size_t, void* holder) {
  delete static_cast<std::shared_ptr<const std::string>*>(holder);
}

size_t Queued(bufferevent* bev) {
  return evbuffer_get_length(bufferevent_get_output(bev));
}

}  // namespace

struct TileFrontEnd::Loop {
  event_base* base = nullptr;
  std::atomic<bool> exited{false};
  evconnlistener* listener = nullptr;
  std::set<Connection*> connections;  // touched by this loop's thread only
};

// One client connection. Requests are taken one at a time, in order: tiles
// are answered here; any other request is relayed to httplib, and the next
// request waits until httplib's answer has ended (ResponseFramer). A chunked
// upload is relayed as it arrives, framed and held to the body limit
// (ChunkedRequestBody). What the front end cannot follow (an answer without
// a length, a protocol switch) turns the connection into a byte-for-byte
// relay for good (`raw`).
struct TileFrontEnd::Connection {
  TileFrontEnd* owner;
  Loop* loop;
  bufferevent* client = nullptr;
  bufferevent* backend = nullptr;              // opened on the first request for httplib
  std::optional<ResponseFramer> in_flight{};   // httplib's answer being relayed
  size_t request_left = 0;                     // bytes of the relayed request still to send
  std::optional<ChunkedRequestBody> chunks{};  // its chunked body, after those bytes
  bool close_after_answer = false;             // the relayed request or its answer ends the connection
  bool raw = false;
  bool close_after_write = false;
  bool client_eof = false;

  ~Connection() {
    if (client) bufferevent_free(client);
    DropBackend();
  }

  void DropBackend() {
    if (!backend) return;
    bufferevent_free(backend);
    backend = nullptr;
    --owner->proxied_;
  }

  static void Close(Connection* c) {
    c->loop->connections.erase(c);
    delete c;
  }

  // Takes the requests in the input, in order, as far as it can now.
  void Serve() {
    evbuffer* in = bufferevent_get_input(client);
    while (!close_after_write) {
      if (raw) return Relay(client, backend);
      if (in_flight) return SendRequest();
      const RequestHead h = NextHead(in);
      switch (h.kind) {
        case RequestHead::Kind::kNeedMore:
          return;
        case RequestHead::Kind::kRefuse:
          return Refuse(h.status, h.error);
        case RequestHead::Kind::kTile:
          if (std::optional<TileAnswer> a = owner->tiles_(h.mission_id, h.tile_path, h.if_none_match)) {
            Answer(h, *a);
            evbuffer_drain(in, h.size);
            break;
          }
          [[fallthrough]];  // not ours (an unknown mission, say): the backend answers
        case RequestHead::Kind::kBackend:
          if (!OpenBackend()) return;
          in_flight.emplace(h.head_only);
          request_left = h.size + h.body_bytes;
          if (h.chunked) chunks.emplace(owner->max_body_bytes_);
          close_after_answer = !h.keep_alive;
          break;
      }
    }
  }

  void Answer(const RequestHead& r, const TileAnswer& a) {
    std::string head;
    head.reserve(256);
    head += "HTTP/1.1 ";
    head += std::to_string(a.status);
    head += ' ';
    head += Reason(a.status);
    head += "\r\n";
    for (const auto& [name, value] : a.headers) head += name + ": " + value + "\r\n";
    if (a.body) head += "Content-Type: " + a.content_type + "\r\n";
    if (a.status != 304) head += "Content-Length: " + std::to_string(a.body ? a.body->size() : 0) + "\r\n";
    // An HTTP/1.0 client closes unless told the connection stays open.
    head += !r.keep_alive ? "Connection: close\r\n\r\n" : r.http_1_0 ? "Connection: keep-alive\r\n\r\n" : "\r\n";
    evbuffer* out = bufferevent_get_output(client);
    evbuffer_add(out, head.data(), head.size());
    if (a.body && !r.head_only && !a.body->empty()) {
      // The cached tile's bytes go out without a copy; the holder keeps them alive.
      auto* holder = new std::shared_ptr<const std::string>(a.body);
      evbuffer_add_reference(out, (*holder)->data(), (*holder)->size(), FreeBody, holder);
    }
    if (!r.keep_alive) StopReading();
  }

  // A head that is not HTTP/1.x or is too long: 400 (414, 431, 501, 505),
  // and the connection ends (where the next request would start is
  // unknown). Also a chunked body that is malformed or too large (400, 413).
  void Refuse(int status, const std::string& error) {
    const std::string body = "{\"error\":\"" + std::string(status == 400 ? "bad request: " : "") + error + "\"}";
    const std::string reply = "HTTP/1.1 " + std::to_string(status) + " " + Reason(status) +
                              "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
                              "\r\nConnection: close\r\n\r\n" + body;
    evbuffer_add(bufferevent_get_output(client), reply.data(), reply.size());
    StopReading();
  }

  void StopReading() {
    close_after_write = true;
    bufferevent_disable(client, EV_READ);
  }

  // Reads the client again once what held it up has cleared.
  void ResumeReading() {
    if (close_after_write || client_eof || Queued(client) > kMaxQueuedBytes) return;
    if (backend && Queued(backend) > kMaxQueuedBytes) return;
    bufferevent_enable(client, EV_READ);
  }

  // Sends what was queued for the client now (one writev for every reply to
  // this read). The socket is watched for writing only while a reply did not
  // fit: registering and unregistering it around every reply cost two
  // epoll_ctl calls per tile. True when the connection is gone.
  bool Flush() {
    // The client stopped writing: close once all it asked for is answered,
    // or at once when a request for httplib was cut short, unless httplib
    // has begun to answer it already (e.g. a 403 sent before the body was
    // read): that answer goes out whole first.
    const bool answering = in_flight && !in_flight->between_answers();
    if (client_eof && !raw && (!in_flight || (RequestPending() && !answering)) && !close_after_write) StopReading();
    evbuffer* out = bufferevent_get_output(client);
    if (evbuffer_get_length(out) > 0) {
      // bufferevent keeps its output's start frozen outside its own write
      // callback; without thawing it this write fails and the reply waits
      // for the next loop iteration, in 16 KiB writes.
      evbuffer_unfreeze(out, 1);
      evbuffer_write(out, bufferevent_getfd(client));
      evbuffer_freeze(out, 1);
    }
    if (evbuffer_get_length(out) > 0) {
      bufferevent_enable(client, EV_WRITE);
      if (evbuffer_get_length(out) > kMaxQueuedBytes) {
        bufferevent_disable(client, EV_READ);
        if (backend) bufferevent_disable(backend, EV_READ);
      }
      return false;
    }
    bufferevent_disable(client, EV_WRITE);
    if (!close_after_write) return false;
    Close(this);
    return true;
  }

  bool OpenBackend() {
    if (backend) return true;
    backend = bufferevent_socket_new(loop->base, -1, BEV_OPT_CLOSE_ON_FREE);
    ++owner->proxied_;
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<uint16_t>(owner->backend_port_));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bufferevent_setcb(backend, OnBackendRead, OnBackendWrite, OnBackendEvent, this);
    if (bufferevent_socket_connect(backend, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0) {
      StopReading();
      return false;
    }
    bufferevent_enable(backend, EV_READ | EV_WRITE);
    return true;
  }

  // Part of the relayed request has still to come from the client.
  bool RequestPending() const { return request_left > 0 || (chunks && !chunks->done()); }

  // Sends what has arrived of the relayed request.
  void SendRequest() {
    evbuffer* in = bufferevent_get_input(client);
    const size_t n = std::min(request_left, evbuffer_get_length(in));
    evbuffer_remove_buffer(in, bufferevent_get_output(backend), n);
    request_left -= n;
    if (request_left == 0 && chunks && !chunks->done()) {
      const size_t body = Frame(in, &*chunks);
      if (chunks->refused()) return RefuseBody();
      evbuffer_remove_buffer(in, bufferevent_get_output(backend), body);
    }
    if (Queued(backend) > kMaxQueuedBytes) bufferevent_disable(client, EV_READ);
  }

  // A chunked body over the limit or malformed: httplib, which has part of
  // it, is hung up on (it gives the request up); the client gets the answer
  // and the connection closes, the rest of its body unread.
  void RefuseBody() {
    const bool between_answers = in_flight->between_answers();  // e.g. after a "100 Continue"
    DropBackend();
    in_flight.reset();
    const ChunkedRequestBody body = std::move(*chunks);
    chunks.reset();
    if (between_answers) return Refuse(body.status(), body.error());
    StopReading();  // httplib had begun an answer: it cannot be followed by ours
  }

  // Raw mode and the client said all it will say: httplib is not told (a
  // half-close would make it drop an answer it is still writing: it peeks for
  // the end of input before each write). Its keep-alive timeout ends the
  // connection, and OnBackendEvent then closes the client's.
  // Moves everything `from` read to `to` (raw mode).
  static void Relay(bufferevent* from, bufferevent* to) {
    evbuffer_add_buffer(bufferevent_get_output(to), bufferevent_get_input(from));
    if (Queued(to) > kMaxQueuedBytes) bufferevent_disable(from, EV_READ);
  }

  static void OnClientRead(bufferevent*, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    c->Serve();
    if (c->Flush()) return;
    // Requests that wait behind a relayed one are not read without end.
    if (evbuffer_get_length(bufferevent_get_input(c->client)) > kMaxQueuedBytes)
      bufferevent_disable(c->client, EV_READ);
  }

  static void OnClientWrite(bufferevent*, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    if (c->Flush()) return;
    c->ResumeReading();
    if (c->backend && Queued(c->client) <= kMaxQueuedBytes) bufferevent_enable(c->backend, EV_READ);
  }

  static void OnClientEvent(bufferevent*, short what, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    if (!(what & BEV_EVENT_EOF)) {
      if (what & (BEV_EVENT_ERROR | BEV_EVENT_TIMEOUT)) Close(c);
      return;
    }
    // Answer what was asked before the client stopped writing, then close.
    c->client_eof = true;
    c->Serve();
    c->Flush();
  }

  // httplib's answer: relayed up to its end, then the next request is taken.
  static void OnBackendRead(bufferevent* bev, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    evbuffer* in = bufferevent_get_input(bev);
    if (!c->raw && c->in_flight) {
      evbuffer_remove_buffer(in, bufferevent_get_output(c->client), Frame(in, &*c->in_flight));
      if (c->in_flight->lost()) {
        c->raw = true;
      } else if (c->in_flight->done()) {
        // Answered before the whole request was sent: where the next one starts is unknown.
        if (c->close_after_answer || c->in_flight->close() || c->RequestPending()) c->StopReading();
        c->in_flight.reset();
        c->chunks.reset();
        c->raw = evbuffer_get_length(in) > 0;  // more than was asked for: stop following
        c->Serve();
        c->ResumeReading();
      }
    } else if (!c->raw) {
      c->raw = evbuffer_get_length(in) > 0;  // an answer to nothing: stop following
    }
    if (c->raw) Relay(bev, c->client);
    c->Flush();
  }

  static void OnBackendWrite(bufferevent*, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    c->ResumeReading();
  }

  static void OnBackendEvent(bufferevent* bev, short what, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    if (what & BEV_EVENT_CONNECTED) return;
    // httplib closed (or failed). A failed write can come first when it
    // closed without reading all we sent: take what it answered before.
    while (evbuffer_read(bufferevent_get_input(bev), bufferevent_getfd(bev), 1 << 16) > 0) {
    }
    if (!c->raw && !c->in_flight && evbuffer_get_length(bufferevent_get_input(bev)) == 0) {
      c->DropBackend();  // an idle connection httplib timed out: the next request opens another
      return;
    }
    // Pass on what it sent, then close the client: where its answer ended is unknown.
    evbuffer_add_buffer(bufferevent_get_output(c->client), bufferevent_get_input(bev));
    c->StopReading();
    c->Flush();
  }
};

namespace {

void OnAccept(evconnlistener*, evutil_socket_t fd, sockaddr*, int, void* arg) {
  auto* ctx = static_cast<std::pair<TileFrontEnd*, TileFrontEnd::Loop*>*>(arg);
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  // Room for a few whole tiles, so a reply goes out in one writev.
  int send_buffer = 512 << 10;
  setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &send_buffer, sizeof send_buffer);
  auto* c = new TileFrontEnd::Connection{ctx->first, ctx->second};
  c->client = bufferevent_socket_new(ctx->second->base, fd, BEV_OPT_CLOSE_ON_FREE);
  bufferevent_setcb(c->client, TileFrontEnd::Connection::OnClientRead, TileFrontEnd::Connection::OnClientWrite,
                    TileFrontEnd::Connection::OnClientEvent, c);
  bufferevent_set_max_single_write(c->client, 1 << 20);  // a whole tile per write, not 16 KiB
  bufferevent_enable(c->client, EV_READ);                // EV_WRITE only while a reply waits (FlushNow)
  ctx->second->connections.insert(c);
}

std::once_flag g_threads_once;

}  // namespace

TileFrontEnd::TileFrontEnd(TileResolver tiles, int backend_port, int loops, size_t max_body_bytes)
    : tiles_(std::move(tiles)), backend_port_(backend_port), max_body_bytes_(max_body_bytes) {
  std::call_once(g_threads_once, [] { evthread_use_pthreads(); });  // loops are stopped from other threads
  for (int i = 0; i < std::max(1, loops); ++i) loops_.push_back(std::make_unique<Loop>());
}

TileFrontEnd::~TileFrontEnd() {
  Stop();
  for (auto& loop : loops_) {
    for (Connection* c : loop->connections) delete c;
    loop->connections.clear();
    if (loop->listener) evconnlistener_free(loop->listener);
    if (loop->base) event_base_free(loop->base);
  }
  if (listen_fd_ >= 0) close(listen_fd_);
}

int TileFrontEnd::Bind(const std::string& host, int port) {
  addrinfo hints{}, *found = nullptr;
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  if (getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found) != 0 || !found)
    throw InputError("", 0, "--host", "cannot listen on '" + host + "' (not an address of this machine)");
  listen_fd_ = socket(found->ai_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  int one = 1;
  // SO_REUSEADDR only (a quick restart); never SO_REUSEPORT, so a second
  // server on the same port fails instead of taking half the connections.
  setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  const bool bound = listen_fd_ >= 0 && ::bind(listen_fd_, found->ai_addr, found->ai_addrlen) == 0 &&
                     ::listen(listen_fd_, SOMAXCONN) == 0;
  freeaddrinfo(found);
  if (!bound)
    throw InputError("", 0, "--port",
                     "cannot listen on " + host + ":" + std::to_string(port) +
                         " (in use, or not allowed); pick another with --port");
  sockaddr_storage addr{};
  socklen_t len = sizeof addr;
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &len);
  const int actual = addr.ss_family == AF_INET6 ? ntohs(reinterpret_cast<sockaddr_in6*>(&addr)->sin6_port)
                                                : ntohs(reinterpret_cast<sockaddr_in*>(&addr)->sin_port);
  // Every loop waits on the same listening socket; whichever wakes first accepts.
  for (auto& loop : loops_) {
    // With the changelist, the write interest a reply adds and removes within
    // one loop iteration costs no epoll_ctl calls.
    event_config* config = event_config_new();
    event_config_set_flag(config, EVENT_BASE_FLAG_EPOLL_USE_CHANGELIST);
    loop->base = event_base_new_with_config(config);
    event_config_free(config);
    auto* ctx = new std::pair<TileFrontEnd*, Loop*>(this, loop.get());
    loop->listener = evconnlistener_new(loop->base, OnAccept, ctx, 0, -1, listen_fd_);
    evconnlistener_set_error_cb(loop->listener, nullptr);
    contexts_.emplace_back(ctx);
  }
  return actual;
}

void TileFrontEnd::Start() {
  if (started_) return;
  started_ = true;
  for (auto& loop : loops_)
    threads_.emplace_back([l = loop.get()] {
      event_base_loop(l->base, EVLOOP_NO_EXIT_ON_EMPTY);
      l->exited = true;
    });
}

void TileFrontEnd::Stop() {
  if (!started_) return;
  started_ = false;
  // A loop that has not started yet clears a break request when it does:
  // repeat the request until every loop has ended.
  for (auto& loop : loops_) {
    while (!loop->exited) {
      event_base_loopbreak(loop->base);
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
  }
  for (auto& t : threads_) t.join();
  threads_.clear();
}

}  // namespace seamap::server
