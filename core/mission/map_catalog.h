#pragma once
// The maps in a folder, for a catalogue of missions: every NAME.mbtiles and
// every tile folder (a subfolder with metadata.json), each with a unique
// URL-safe id and what an index shows. A file that cannot be read (half
// written, not SQLite, no tiles table) is listed as unavailable with the
// reason instead of failing the scan. Knows nothing of HTTP.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/geo/web_mercator.h"

namespace seamap {

struct CatalogEntry {
  std::string id;    // [a-z0-9_-]+ from the file name, "-2", "-3"... on a clash
  std::string path;  // the map, as OpenExistingMap takes it
  bool available = false;
  std::string reason;  // why not available
  std::string name;    // metadata "name", else the file name
  std::string state;   // seamap_state: building, complete, stopped ("complete" when absent), or
                       // interrupted (building, but no process holds its lock: core/mission/build_state.h)
  std::string format;  // tile extension
  std::optional<LatLonBounds> bounds;
  int min_zoom = 0, max_zoom = 0;
  int64_t frames = 0;                               // frames recorded
  std::optional<double> first_time_s, last_time_s;  // the frames' navigation times
  int64_t modified_unix_s = 0;                      // last change of the file (or its WAL)
  std::vector<std::string> layers;                  // as seamap_layers: the first is the map itself
};

class MapCatalog {
 public:
  // Throws InputError(folder, 0, "", ...) unless `folder` is a readable folder.
  explicit MapCatalog(std::string folder);

  // Reads the folder again: new maps appear, removed ones go; a map is re-read
  // only when its file (or WAL, or metadata.json) changed. Sorted by id.
  std::vector<CatalogEntry> Scan();

  const std::string& folder() const { return folder_; }

 private:
  struct Seen {
    std::string signature;  // sizes and times of the files that make the map
    CatalogEntry entry;
  };
  std::string folder_;
  std::map<std::string, Seen> seen_;  // by path
};

// "Dive 12 (north).mbtiles" -> "dive-12-north".
std::string CatalogId(const std::string& file_name);

}  // namespace seamap
