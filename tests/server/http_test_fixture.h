#pragma once
// Shared by the HTTP API tests (http_*_test.cc): a real mission file, a real
// HttpServer on loopback (port 0), raw-socket and event-stream helpers.
#include "server/http_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <fstream>
#include <functional>
#include <iterator>
#include <thread>

#include <gtest/gtest.h>
#include <httplib.h>
#include <opencv2/imgcodecs.hpp>

#include "core/tiles/folder_store.h"
#include "core/util/error.h"
#include "tests/server/test_mission.h"
#include "tests/testing/temp_dir.h"

namespace seamap::server::http_test {

using nlohmann::json;
using test::QuotedVersion;
using test::Text;

constexpr auto kPatience = std::chrono::seconds(30);  // generous: never a timing assertion

inline std::string ReadAll(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline std::vector<int64_t> FeatureIds(const json& collection) {
  std::vector<int64_t> ids;
  for (const auto& f : collection.at("features")) ids.push_back(f.at("id").get<int64_t>());
  return ids;
}

inline std::vector<int> FrameIds(const json& answer) {
  std::vector<int> ids;
  for (const auto& f : answer.at("frames")) ids.push_back(f.at("id").get<int>());
  return ids;
}

// A response as it came off the wire: status code and the raw text.
struct RawResponse {
  int status = 0;
  std::string text;
};

// Sends the request line exactly as given (no normalisation, no encoding).
inline RawResponse RawGet(int port, const std::string& target) {
  RawResponse out;
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return out;
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  ::inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  timeval timeout{30, 0};
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
    const std::string request = "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n";
    if (::send(fd, request.data(), request.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(request.size())) {
      char buf[4096];
      ssize_t n;
      while ((n = ::recv(fd, buf, sizeof buf, 0)) > 0) out.text.append(buf, static_cast<size_t>(n));
    }
  }
  ::close(fd);
  if (out.text.rfind("HTTP/1.1 ", 0) == 0) out.status = std::atoi(out.text.c_str() + 9);
  return out;
}

struct SseEvent {
  std::string id, type, data;
};

// Parses "id: N\nevent: T\ndata: D\n\n" blocks; comments and retry lines are skipped.
inline std::vector<SseEvent> ParseEvents(const std::string& text) {
  std::vector<SseEvent> out;
  size_t start = 0;
  while (true) {
    const size_t end = text.find("\n\n", start);
    if (end == std::string::npos) break;
    SseEvent e;
    std::stringstream block(text.substr(start, end - start));
    std::string line;
    while (std::getline(block, line)) {
      if (line.rfind("id: ", 0) == 0) e.id = line.substr(4);
      if (line.rfind("event: ", 0) == 0) e.type = line.substr(7);
      if (line.rfind("data: ", 0) == 0) e.data = line.substr(6);
    }
    if (!e.type.empty()) out.push_back(e);
    start = end + 2;
  }
  return out;
}

// An open GET /api/events in a thread of its own, collecting what arrives.
class EventStream {
 public:
  EventStream(int port, httplib::Headers headers = {}, std::string target = "/api/events")
      : client_("127.0.0.1", port), target_(std::move(target)) {
    client_.set_read_timeout(120);
    for (const auto& [k, v] : headers) headers_sent_.emplace(k, v);
    thread_ = std::thread([this] {
      auto res = client_.Get(
          target_.c_str(), headers_sent_,
          [this](const httplib::Response& r) {
            std::lock_guard<std::mutex> lock(mutex_);
            status_ = r.status;
            headers_ = r.headers;
            changed_.notify_all();
            return true;
          },
          [this](const char* data, size_t n) {
            std::lock_guard<std::mutex> lock(mutex_);
            data_.append(data, n);
            changed_.notify_all();
            return !stop_;
          });
      std::lock_guard<std::mutex> lock(mutex_);
      ended_ = true;
      changed_.notify_all();
    });
  }
  ~EventStream() { Close(); }

  void Close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    client_.stop();
    if (thread_.joinable()) thread_.join();
  }
  // Waits (generously) until the received text satisfies `done`.
  bool WaitFor(const std::function<bool(const std::string&)>& done) {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, kPatience, [&] { return done(data_) || ended_; }) && done(data_);
  }
  bool WaitForEvents(size_t n) {
    return WaitFor([n](const std::string& text) { return ParseEvents(text).size() >= n; });
  }
  bool WaitForEnd() {
    std::unique_lock<std::mutex> lock(mutex_);
    return changed_.wait_for(lock, kPatience, [&] { return ended_; });
  }
  std::vector<SseEvent> Events() {
    std::lock_guard<std::mutex> lock(mutex_);
    return ParseEvents(data_);
  }
  int status() {
    std::lock_guard<std::mutex> lock(mutex_);
    return status_;
  }
  std::string header(const std::string& name) {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = headers_.find(name);
    return it == headers_.end() ? "" : it->second;
  }

 private:
  httplib::Client client_;
  std::string target_;
  httplib::Headers headers_sent_;
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable changed_;
  std::string data_;
  int status_ = 0;
  httplib::Headers headers_;
  bool stop_ = false, ended_ = false;
};

inline bool Greeted(const std::string& text) {
  return text.find(": seamap events") != std::string::npos;
}

class HttpServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    seamap::testing::WriteFile(web_ / "index.html", "<!doctype html><title>SeaMap console</title>");
    seamap::testing::WriteFile(web_ / "js" / "app.js", "console.log('seamap');");
    seamap::testing::WriteFile(dir_ / "secret.txt", "TOP SECRET");
  }
  void TearDown() override {
    if (server_) server_->Stop();
  }

  ServerOptions Options() const {
    ServerOptions o;
    o.host = "127.0.0.1";
    o.port = 0;
    o.web_dir = web_.string();
    o.threads = 8;
    o.max_streams = 4;
    return o;
  }
  // Serves the test mission as `seamap serve` does; `writable` false: a read-only mission.
  void Start(ServerOptions options, bool writable = true) {
    tiles_ = std::make_unique<TileSource>(mission_.path.string(), readers_);
    writer_ = std::make_unique<MBTilesStore>(mission_.path.string(),
                                             writable ? MBTilesStore::Mode::kCreate : MBTilesStore::Mode::kReadOnly);
    state_.Load(*writer_);
    state_.SetLayers(tiles_->Layers(), tiles_->Format());
    registry_ = std::make_unique<DetectionRegistry>(writable ? writer_.get() : nullptr, &events_);
    registry_->Load(*writer_);
    server_ = std::make_unique<HttpServer>(options, tiles_.get(), &state_, registry_.get(), &events_);
    server_->Bind();
    server_->Start();
    ASSERT_GT(server_->port(), 0);
  }
  void Start() { Start(Options()); }

  std::unique_ptr<httplib::Client> Client() const {
    auto c = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    c->set_read_timeout(60);
    c->set_connection_timeout(30);
    return c;
  }
  httplib::Result Get(const std::string& path, const httplib::Headers& headers = {}) {
    return Client()->Get(path.c_str(), headers);
  }
  json GetJson(const std::string& path, int expected_status = 200) {
    auto res = Get(path);
    EXPECT_TRUE(res) << path;
    if (!res) return nullptr;
    EXPECT_EQ(res->status, expected_status) << path << ": " << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json") << path;
    try {
      return json::parse(res->body);
    } catch (const json::exception& e) {
      ADD_FAILURE() << path << ": not JSON: " << res->body;
      return nullptr;
    }
  }
  // The answer must be a JSON error whose message contains `needle`.
  void ExpectError(const httplib::Result& res, int status, const std::string& needle, const std::string& what) {
    ASSERT_TRUE(res) << what;
    EXPECT_EQ(res->status, status) << what << ": " << res->body;
    EXPECT_EQ(res->get_header_value("Content-Type"), "application/json") << what;
    json body = json::parse(res->body, nullptr, false);
    ASSERT_TRUE(body.is_object()) << what << ": " << res->body;
    ASSERT_TRUE(body.contains("error") && body["error"].is_string()) << what << ": " << res->body;
    EXPECT_NE(body["error"].get<std::string>().find(needle), std::string::npos)
        << what << ": " << body["error"].get<std::string>();
  }
  // Detections as a fresh reader of the MBTiles file sees them.
  std::map<int64_t, Detection> StoredDetections() const {
    MBTilesStore reader(mission_.path.string(), MBTilesStore::Mode::kReadOnly);
    std::map<int64_t, Detection> out;
    for (const auto& d : reader.Detections()) out[d.id] = d;
    return out;
  }
  static json Mark(double lon, double lat, const std::string& cls) {
    return {{"type", "Feature"},
            {"geometry", {{"type", "Point"}, {"coordinates", {lon, lat}}}},
            {"properties", {{"class", cls}}}};
  }

  int readers_ = 2;
  seamap::testing::TempDir dir_;
  test::TestMission mission_ = test::WriteTestMission(dir_.path());
  std::filesystem::path web_ = dir_ / "web";
  EventHub events_;
  MissionState state_;
  std::unique_ptr<TileSource> tiles_;
  std::unique_ptr<MBTilesStore> writer_;
  std::unique_ptr<DetectionRegistry> registry_;
  std::unique_ptr<HttpServer> server_;  // last: stopped and destroyed first
};

// --- tiles -------------------------------------------------------------------

}  // namespace seamap::server::http_test
