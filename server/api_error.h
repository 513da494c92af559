#pragma once
// An answer other than success, with the HTTP status and a message that
// names the parameter and what was expected.
#include <stdexcept>
#include <string>

namespace seamap::server {

class ApiError : public std::runtime_error {
 public:
  ApiError(int status, const std::string& message) : std::runtime_error(message), status_(status) {}
  int status() const { return status_; }

 private:
  int status_;
};

}  // namespace seamap::server
