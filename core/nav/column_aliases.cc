#include "core/nav/column_aliases.h"

#include <cctype>
#include <utility>

#include "core/nav/csv_table.h"
#include "core/util/error.h"

namespace seamap {
namespace {

const std::vector<std::pair<std::string, std::vector<std::string>>>& Aliases() {
  static const std::vector<std::pair<std::string, std::vector<std::string>>> table = {
      {"image", {"image", "filename", "file", "image_name", "photo", "frame", "file_name", "image_file", "img"}},
      {"time_s", {"time_s", "time", "t", "timestamp", "seconds", "time_sec"}},
      {"x_m", {"x_m", "x", "east", "east_m", "easting_local"}},
      {"y_m", {"y_m", "y", "north", "north_m", "northing_local"}},
      {"lat", {"lat", "latitude", "lat_deg"}},
      {"lon", {"lon", "lng", "long", "longitude", "lon_deg"}},
      {"easting", {"easting", "easting_m", "utm_easting", "utm_e"}},
      {"northing", {"northing", "northing_m", "utm_northing", "utm_n"}},
      {"utm_zone", {"utm_zone", "zone"}},
      {"altitude_m", {"altitude_m", "alt", "altitude", "alt_m", "height"}},
      {"depth_m", {"depth_m", "depth"}},
      {"heading_deg", {"heading_deg", "heading", "yaw", "yaw_deg", "hdg"}},
      {"pitch_deg", {"pitch_deg", "pitch"}},
      {"roll_deg", {"roll_deg", "roll"}},
      // GPS quality (a buoy's fixes) and the georeferenced keyframes' mark.
      {"sigma_m", {"sigma_m", "sigma", "h_sigma", "hacc", "horizontal_accuracy", "accuracy_m", "std_m"}},
      {"hdop", {"hdop"}},
      {"fix_quality", {"fix_quality", "quality", "gps_quality", "fix"}},
      {"good", {"good"}},
  };
  return table;
}

std::string Join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + Shorten(item);
  return out;
}

}  // namespace

std::string NormalizeColumnName(const std::string& name) {
  std::string out;
  int depth = 0;
  for (unsigned char c : name) {
    if (c == '(' || c == '[')
      ++depth;
    else if ((c == ')' || c == ']') && depth > 0)
      --depth;
    else if (depth == 0)
      out += static_cast<char>(std::tolower(c));
  }
  // Trim, then spaces and dashes inside the name become '_'.
  const size_t begin = out.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  out = out.substr(begin, out.find_last_not_of(" \t") - begin + 1);
  for (char& c : out)
    if (c == ' ' || c == '-' || c == '\t') c = '_';
  return out;
}

std::string CanonicalColumn(const std::string& name) {
  const std::string key = NormalizeColumnName(name);
  for (const auto& [canonical, names] : Aliases())
    for (const auto& alias : names)
      if (alias == key) return canonical;
  return "";
}

std::string AcceptedNames(const std::string& canonical) {
  for (const auto& [name, names] : Aliases())
    if (name == canonical) return Join(names);
  return "";
}

bool IsCanonicalColumn(const std::string& name) {
  for (const auto& entry : Aliases())
    if (entry.first == name) return true;
  return false;
}

ColumnMap MapColumns(const std::vector<std::string>& header, const std::map<std::string, std::string>& extra,
                     const std::string& path, int header_line) {
  ColumnMap map;
  std::vector<bool> taken(header.size(), false);
  for (const auto& [canonical, file_name] : extra) {
    if (!IsCanonicalColumn(canonical)) {
      std::vector<std::string> known;
      for (const auto& entry : Aliases()) known.push_back(entry.first);
      throw InputError(path, header_line, canonical, "unknown column in the column mapping; known: " + Join(known));
    }
    const std::string wanted = NormalizeColumnName(file_name);
    bool found = false;
    for (size_t i = 0; i < header.size() && !found; ++i) {
      if (NormalizeColumnName(header[i]) != wanted) continue;
      map.index[canonical] = static_cast<int>(i);
      taken[i] = found = true;
    }
    if (!found)
      throw InputError(
          path, header_line, canonical,
          "column '" + file_name + "' (from the column mapping) is not in the header; found: " + Join(header));
  }
  for (size_t i = 0; i < header.size(); ++i) {
    if (taken[i]) continue;
    const std::string canonical = CanonicalColumn(header[i]);
    if (canonical.empty()) {
      if (!header[i].empty()) map.unknown.push_back(header[i]);
    } else if (map.Has(canonical)) {
      map.repeated.push_back(header[i]);
    } else {
      map.index[canonical] = static_cast<int>(i);
    }
  }
  return map;
}

}  // namespace seamap
