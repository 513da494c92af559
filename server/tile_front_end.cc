#include "server/tile_front_end.h"

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
#include <cctype>
#include <chrono>
#include <cstring>
#include <mutex>
#include <optional>
#include <set>
#include <thread>

#include "core/util/error.h"
#include "server/mission_state.h"
#include "server/tile_answer.h"

namespace seamap::server {
namespace {

constexpr size_t kMaxHead = 8192;  // longer heads go to httplib, which refuses them properly

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
    default:
      return "Internal Server Error";
  }
}

// What the front end needs of a request head; `fast` is false for anything
// that is not a plain tile GET/HEAD (those are passed to httplib untouched).
struct Head {
  bool fast = false;
  bool head_only = false;  // HEAD
  bool close = false;      // the client wants the connection closed after the answer
  std::string path;        // after "/tiles/", query removed
  std::optional<std::string> if_none_match;
};

bool IEquals(const std::string& a, const char* b) {
  const size_t n = std::strlen(b);
  if (a.size() != n) return false;
  for (size_t i = 0; i < n; ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) != b[i]) return false;
  return true;
}

Head ParseHead(const std::string& head) {
  Head h;
  const size_t line_end = head.find("\r\n");
  const std::string line = head.substr(0, line_end);
  const size_t s1 = line.find(' '), s2 = line.rfind(' ');
  if (s1 == std::string::npos || s2 == s1) return h;
  const std::string method = line.substr(0, s1), target = line.substr(s1 + 1, s2 - s1 - 1),
                    version = line.substr(s2 + 1);
  if (method != "GET" && method != "HEAD") return h;
  if (version != "HTTP/1.1" && version != "HTTP/1.0") return h;
  std::string path = target.substr(0, target.find('?'));
  // Escapes and dot segments are httplib's to decode and refuse.
  if (path.rfind("/tiles/", 0) != 0 || path.find('%') != std::string::npos || path.find("..") != std::string::npos)
    return h;
  if (path.size() > 5 && path.compare(path.size() - 5, 5, ".json") == 0) return h;
  h.path = path.substr(7);
  h.head_only = method == "HEAD";
  bool keep_alive = version == "HTTP/1.1";
  size_t pos = line_end + 2;
  while (pos < head.size()) {
    const size_t end = head.find("\r\n", pos);
    if (end == std::string::npos || end == pos) break;
    const std::string field = head.substr(pos, end - pos);
    pos = end + 2;
    const size_t colon = field.find(':');
    if (colon == std::string::npos) return Head{};
    const std::string name = field.substr(0, colon);
    std::string value = field.substr(colon + 1);
    value.erase(0, value.find_first_not_of(" \t"));
    value.erase(value.find_last_not_of(" \t") + 1);
    if (IEquals(name, "content-length") && value != "0") return Head{};  // a GET with a body
    if (IEquals(name, "transfer-encoding")) return Head{};
    if (IEquals(name, "if-none-match")) h.if_none_match = value;
    if (IEquals(name, "connection")) {
      std::string v = value;
      std::transform(v.begin(), v.end(), v.begin(), [](unsigned char c) { return std::tolower(c); });
      if (v.find("close") != std::string::npos) keep_alive = false;
      if (v.find("keep-alive") != std::string::npos) keep_alive = true;
    }
  }
  h.close = !keep_alive;
  h.fast = true;
  return h;
}

void FreeBody(const void*, size_t, void* holder) {
  delete static_cast<std::shared_ptr<const std::string>*>(holder);
}

}  // namespace

struct TileFrontEnd::Loop {
  event_base* base = nullptr;
  std::atomic<bool> exited{false};
  evconnlistener* listener = nullptr;
  std::set<Connection*> connections;  // touched by this loop's thread only
};

struct TileFrontEnd::Connection {
  TileFrontEnd* owner;
  Loop* loop;
  bufferevent* client = nullptr;
  bufferevent* backend = nullptr;
  bool close_after_write = false;
  bool client_eof = false;

  ~Connection() {
    if (client) bufferevent_free(client);
    if (backend) {
      bufferevent_free(backend);
      --owner->proxied_;
    }
  }

  static void Close(Connection* c) {
    c->loop->connections.erase(c);
    delete c;
  }

  // Tile mode: answer every complete request head in the input.
  static void OnClientRead(bufferevent* bev, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    if (c->backend) return Forward(bev, c->backend);
    c->AnswerAll();
    if (c->backend) return;
    c->FlushNow();
    if (c->close_after_write && evbuffer_get_length(bufferevent_get_output(bev)) == 0) Close(c);
  }

  void AnswerAll() {
    Connection* c = this;
    bufferevent* bev = client;
    evbuffer* in = bufferevent_get_input(bev);
    while (!c->close_after_write) {
      evbuffer_ptr end = evbuffer_search(in, "\r\n\r\n", 4, nullptr);
      if (end.pos < 0) {
        if (evbuffer_get_length(in) > kMaxHead) c->PassThrough();
        return;
      }
      const size_t head_size = static_cast<size_t>(end.pos) + 4;
      if (head_size > kMaxHead) return c->PassThrough();
      std::string head(head_size, '\0');
      evbuffer_copyout(in, head.data(), head_size);
      const Head h = ParseHead(head);
      if (!h.fast) return c->PassThrough();
      evbuffer_drain(in, head_size);
      c->Answer(h);
    }
  }

  void Answer(const Head& h) {
    TileAnswer a = AnswerTile(*owner->tiles_, owner->mission_->building(), h.path, h.if_none_match);
    std::string head = "HTTP/1.1 " + std::to_string(a.status) + " " + Reason(a.status) + "\r\n";
    for (const auto& [name, value] : a.headers) head += name + ": " + value + "\r\n";
    if (a.body) head += "Content-Type: " + a.content_type + "\r\n";
    if (a.status != 304) head += "Content-Length: " + std::to_string(a.body ? a.body->size() : 0) + "\r\n";
    head += h.close ? "Connection: close\r\n\r\n" : "\r\n";
    evbuffer* out = bufferevent_get_output(client);
    evbuffer_add(out, head.data(), head.size());
    if (a.body && !h.head_only && !a.body->empty()) {
      // The cached tile's bytes go out without a copy; the holder keeps them alive.
      auto* holder = new std::shared_ptr<const std::string>(a.body);
      evbuffer_add_reference(out, (*holder)->data(), (*holder)->size(), FreeBody, holder);
    }
    if (h.close) {
      close_after_write = true;
      bufferevent_disable(client, EV_READ);
    }
  }

  // Sends what the answers put in the output now (one writev for every
  // reply to this read). In tile mode the socket is watched for writing only
  // while a reply did not fit: registering and unregistering it around every
  // reply cost two epoll_ctl calls per tile.
  void FlushNow() {
    evbuffer* out = bufferevent_get_output(client);
    if (evbuffer_get_length(out) > 0) {
      // bufferevent keeps its output's start frozen outside its own write
      // callback; without thawing it this write fails and the reply waits
      // for the next loop iteration, in 16 KiB writes.
      evbuffer_unfreeze(out, 1);
      evbuffer_write(out, bufferevent_getfd(client));
      evbuffer_freeze(out, 1);
    }
    if (evbuffer_get_length(out) > 0)
      bufferevent_enable(client, EV_WRITE);
    else
      bufferevent_disable(client, EV_WRITE);
  }

  // Everything from here on (including what was read) goes to httplib.
  void PassThrough() {
    bufferevent_enable(client, EV_WRITE);  // httplib's replies flow through the output from now on
    backend = bufferevent_socket_new(loop->base, -1, BEV_OPT_CLOSE_ON_FREE);
    ++owner->proxied_;
    sockaddr_in to{};
    to.sin_family = AF_INET;
    to.sin_port = htons(static_cast<uint16_t>(owner->backend_port_));
    to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bufferevent_setcb(backend, OnBackendRead, OnBackendWrite, OnBackendEvent, this);
    if (bufferevent_socket_connect(backend, reinterpret_cast<sockaddr*>(&to), sizeof to) != 0) {
      close_after_write = true;
      bufferevent_disable(client, EV_READ);
      return;
    }
    bufferevent_enable(backend, EV_READ | EV_WRITE);
    Forward(client, backend);
    if (client_eof) ShutdownBackendWrite();
  }

  static void Forward(bufferevent* from, bufferevent* to) {
    evbuffer_add_buffer(bufferevent_get_output(to), bufferevent_get_input(from));
  }

  void ShutdownBackendWrite() {
    // The client said all it will say; tell httplib once it has everything.
    if (evbuffer_get_length(bufferevent_get_output(backend)) == 0) shutdown(bufferevent_getfd(backend), SHUT_WR);
  }

  static void OnClientWrite(bufferevent* bev, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    const bool drained = evbuffer_get_length(bufferevent_get_output(bev)) == 0;
    if (c->close_after_write && drained) return Close(c);
    if (!c->backend && drained) bufferevent_disable(bev, EV_WRITE);
  }

  static void OnClientEvent(bufferevent*, short what, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    if (what & BEV_EVENT_EOF) {
      c->client_eof = true;
      if (c->backend) return c->ShutdownBackendWrite();
      // Answer what was asked before the client stopped writing, then close.
      c->AnswerAll();
      if (c->backend) return c->ShutdownBackendWrite();
      c->close_after_write = true;
      c->FlushNow();
      if (evbuffer_get_length(bufferevent_get_output(c->client)) == 0) Close(c);
      return;
    }
    if (what & (BEV_EVENT_ERROR | BEV_EVENT_TIMEOUT)) Close(c);
  }

  static void OnBackendRead(bufferevent* bev, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    Forward(bev, c->client);
  }

  static void OnBackendWrite(bufferevent*, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    if (c->client_eof) c->ShutdownBackendWrite();
  }

  static void OnBackendEvent(bufferevent* bev, short what, void* arg) {
    auto* c = static_cast<Connection*>(arg);
    if (what & BEV_EVENT_CONNECTED) return;
    // httplib closed (or failed): pass on what it sent, then close the client.
    Forward(bev, c->client);
    c->close_after_write = true;
    bufferevent_disable(c->client, EV_READ);
    if (evbuffer_get_length(bufferevent_get_output(c->client)) == 0) Close(c);
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

TileFrontEnd::TileFrontEnd(TileSource* tiles, MissionState* mission, int backend_port, int loops)
    : tiles_(tiles), mission_(mission), backend_port_(backend_port) {
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
