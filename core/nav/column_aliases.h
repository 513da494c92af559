#pragma once
// Navigation column names: the canonical names (image, time_s, x_m, ...), the
// aliases understood for each, and the mapping of a header onto them.
#include <map>
#include <string>
#include <vector>

namespace seamap {

// Lower case, units in brackets dropped, spaces and '-' as '_':
// "Altitude (m)" -> "altitude", "Heading [deg]" -> "heading".
std::string NormalizeColumnName(const std::string& name);

// Canonical name for a header name, "" when unknown.
std::string CanonicalColumn(const std::string& name);

// Accepted names for a canonical column, e.g. "alt, altitude, altitude_m, ...".
std::string AcceptedNames(const std::string& canonical);

bool IsCanonicalColumn(const std::string& name);

struct ColumnMap {
  std::map<std::string, int> index;   // canonical name -> column
  std::vector<std::string> unknown;   // header names not understood
  std::vector<std::string> repeated;  // header names whose column was already mapped
  bool Has(const std::string& canonical) const { return index.count(canonical) > 0; }
};

// extra: canonical -> name used in the file (NavReadOptions::columns); these
// win over aliases. Throws InputError(path, header_line, canonical, ...) when
// extra names an unknown canonical column or a column the header lacks.
ColumnMap MapColumns(const std::vector<std::string>& header, const std::map<std::string, std::string>& extra,
                     const std::string& path, int header_line);

}  // namespace seamap
