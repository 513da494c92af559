#pragma once
// Errors that reach the user: each names where the problem is (file, line,
// field or parameter) and what was expected, so the message alone is enough
// to fix the input.
#include <stdexcept>
#include <string>

namespace seamap {

class InputError : public std::runtime_error {
 public:
  // file: path or parameter source ("--origin", "config.json"); line: 1-based, 0 = none;
  // field: column/key/parameter name, may be empty.
  InputError(std::string file, int line, std::string field, std::string message);

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& field() const { return field_; }
  const std::string& detail() const { return detail_; }

 private:
  std::string file_;
  int line_;
  std::string field_;
  std::string detail_;
};

}  // namespace seamap
