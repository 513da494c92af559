#include "core/util/error.h"

namespace seamap {
namespace {
std::string Compose(const std::string& file, int line, const std::string& field, const std::string& message) {
  std::string out = file;
  if (line > 0) out += ":" + std::to_string(line);
  // A bare parameter ("--origin") names itself; inside a file we say which field.
  if (!field.empty()) out += out.empty() ? field : ": field '" + field + "'";
  if (!out.empty()) out += ": ";
  return out + message;
}
}  // namespace

InputError::InputError(std::string file, int line, std::string field, std::string message)
    : std::runtime_error(Compose(file, line, field, message)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)),
      detail_(std::move(message)) {}

}  // namespace seamap
