#pragma once
// What every route of the servers needs: JSON answers and errors, parameters,
// the request body as JSON, the handler guard that turns exceptions into JSON
// errors, the bearer token check, and a listen backlog fit for bursts.
#include <httplib.h>

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "server/api_error.h"

namespace seamap::server {

constexpr size_t kMaxRequestBody = 64 * 1024;

// httplib 0.11 listens with a backlog of 5: a burst of new connections (a
// browser opening six, a load test opening 64) overflows it and the kernel
// drops SYNs, which clients retry only after a second. Calling listen() again
// on the bound socket raises the backlog.
class BacklogServer : public httplib::Server {
 public:
  void RaiseBacklog();
};

// Messages quote what clients sent, which need not be UTF-8: such bytes
// become U+FFFD instead of a 500 from the JSON library.
std::string Dump(const nlohmann::json& j);
void SendJson(httplib::Response& res, const nlohmann::json& j, int status = 200);
void SendError(httplib::Response& res, int status, const std::string& message);

std::optional<std::string> Param(const httplib::Request& req, const char* name);
// A non-negative integer, else ApiError 400 naming `what`.
int64_t ParseId(const std::string& text, const char* what);
// Parameter `name` as a number in [lo, hi], else ApiError 400.
double ParseCoordinate(const httplib::Request& req, const char* name, double lo, double hi);
// The body as JSON (UTF-8), else ApiError 400 saying what is wrong.
nlohmann::json ParseBody(const httplib::Request& req);

// Does the request carry "Authorization: Bearer <token>"? (Always, without a token.)
bool Authorized(const httplib::Request& req, const std::string& token);

// Runs a handler, turning ApiError and other exceptions into JSON errors.
template <typename F>
httplib::Server::Handler Guard(F f) {
  return [f](const httplib::Request& req, httplib::Response& res) {
    try {
      f(req, res);
    } catch (const ApiError& e) {
      SendError(res, e.status(), e.what());
    } catch (const std::exception& e) {
      SendError(res, 500, e.what());
    }
  };
}

}  // namespace seamap::server
