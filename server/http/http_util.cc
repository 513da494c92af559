#include "server/http/http_util.h"

#include <sys/socket.h>

#include <cstdio>

#include "server/http/utf8.h"

namespace seamap::server {

void BacklogServer::RaiseBacklog() {
  ::listen(svr_sock_, SOMAXCONN);
}

std::string Dump(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void SendJson(httplib::Response& res, const nlohmann::json& j, int status) {
  res.status = status;
  res.set_content(Dump(j), "application/json");
}

void SendError(httplib::Response& res, int status, const std::string& message) {
  SendJson(res, {{"error", message}}, status);
}

std::optional<std::string> Param(const httplib::Request& req, const char* name) {
  if (!req.has_param(name)) return std::nullopt;
  return req.get_param_value(name);
}

int64_t ParseId(const std::string& text, const char* what) {
  try {
    size_t used = 0;
    long long v = std::stoll(text, &used);
    if (used == text.size() && v >= 0) return v;
  } catch (const std::exception&) {
  }
  throw ApiError(400, std::string(what) + ": expected a non-negative integer, got '" + text + "'");
}

double ParseCoordinate(const httplib::Request& req, const char* name, double lo, double hi) {
  auto v = Param(req, name);
  if (!v) throw ApiError(400, std::string("parameter '") + name + "' is required");
  try {
    size_t used = 0;
    double d = std::stod(*v, &used);
    if (used == v->size() && d >= lo && d <= hi) return d;
  } catch (const std::exception&) {
  }
  throw ApiError(400, std::string("parameter '") + name + "': expected a number in [" + std::to_string(int(lo)) + ", " +
                          std::to_string(int(hi)) + "], got '" + *v + "'");
}

nlohmann::json ParseBody(const httplib::Request& req) {
  if (auto bad = FirstInvalidUtf8(req.body)) {
    char byte[8];
    std::snprintf(byte, sizeof byte, "0x%02X", static_cast<unsigned char>(req.body[*bad]));
    throw ApiError(400, "body: not valid UTF-8 (byte " + std::string(byte) + " at offset " + std::to_string(*bad) +
                            "); JSON must be UTF-8 (RFC 8259)");
  }
  try {
    return nlohmann::json::parse(req.body);
  } catch (const nlohmann::json::exception& e) {
    throw ApiError(400, std::string("body: expected JSON: ") + e.what());
  }
}

bool Authorized(const httplib::Request& req, const std::string& token) {
  if (token.empty()) return true;
  const std::string header = req.get_header_value("Authorization");
  const std::string expected = "Bearer " + token;
  if (header.size() != expected.size()) return false;
  unsigned char diff = 0;  // constant time: do not leak the token through timing
  for (size_t i = 0; i < header.size(); ++i) diff |= header[i] ^ expected[i];
  return diff == 0;
}

}  // namespace seamap::server
