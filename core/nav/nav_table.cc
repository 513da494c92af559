#include "core/nav/nav_table.h"

namespace seamap {

// "nav.csv:12: altitude_m must be > 0, got -1.2"; the field is named in front
// only when the reason does not start with it.
std::string Rejection::Message() const {
  std::string out = file;
  if (line > 0) out += ":" + std::to_string(line);
  if (!field.empty() && reason.compare(0, field.size(), field) != 0)
    out += (out.empty() ? "" : ": ") + std::string("field '") + field + "'";
  if (!out.empty()) out += ": ";
  return out + reason;
}

}  // namespace seamap
