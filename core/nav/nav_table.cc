#include "core/nav/nav_table.h"

#include "core/nav/split_time.h"
#include "core/util/error.h"

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

void NavReadOptions::Check(const std::string& source) const {
  if (time_columns.empty()) return;
  const std::string problem = SplitTimePartsProblem(time_columns);
  if (!problem.empty()) throw InputError(source, 0, "navigation.time_columns", problem);
  if (columns.count("time_s"))
    throw InputError(source, 0, "navigation.time_columns",
                     "the time comes either from navigation.columns.time_s or from navigation.time_columns, not both");
}

}  // namespace seamap
