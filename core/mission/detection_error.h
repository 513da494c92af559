#pragma once
// Why the detection book refused a request, in its own terms: the server
// answers kNotFound 404, kInvalid 400 and kRefused 403 (server/detection_registry.h);
// the command line names the option behind `field`.
#include <stdexcept>
#include <string>

namespace seamap {

class DetectionError : public std::runtime_error {
 public:
  enum class Kind {
    kNotFound,  // no detection with that id
    kInvalid,   // a malformed body, property or filter value
    kRefused,   // well-formed but not allowed: a read-only mission, a recogniser's position...
  };
  // what() is `message`; `detail` is the message without the field's name
  // (what a caller that names the field its own way prints after it).
  DetectionError(Kind kind, std::string field, std::string detail, std::string message)
      : std::runtime_error(std::move(message)), kind_(kind), field_(std::move(field)), detail_(std::move(detail)) {}
  // "field: detail".
  static DetectionError Invalid(const std::string& field, const std::string& detail) {
    return {Kind::kInvalid, field, detail, field + ": " + detail};
  }

  Kind kind() const { return kind_; }
  const std::string& field() const { return field_; }
  const std::string& detail() const { return detail_; }

 private:
  Kind kind_;
  std::string field_;
  std::string detail_;
};

}  // namespace seamap
