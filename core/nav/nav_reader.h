#pragma once
// Reads navigation: CSV with a header (columns by name, common aliases such as
// filename/latitude/longitude/yaw understood, more via NavReadOptions::columns)
// or the seed paper's text format
//   NAME X(m): 1.0, Y(m): 2.0, Alt(m): 1.6, Heading(deg): 30.0,
// Fatal problems (file missing/empty, no usable header, no position columns,
// origin missing for local positions) throw InputError naming file/line/field.
// Bad lines are skipped and listed in NavTable::rejected.
#include <string>

#include "core/nav/nav_table.h"

namespace seamap {

NavTable ReadNavigation(const std::string& path, const NavReadOptions& options);

}  // namespace seamap
