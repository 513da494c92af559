#include "core/mission/map_catalog.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <set>
#include <sstream>

#include "core/mission/mission_metadata.h"
#include "core/tiles/map_lock.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"

namespace seamap {
namespace fs = std::filesystem;
namespace {

int64_t UnixSeconds(fs::file_time_type t) {
  const auto system = std::chrono::time_point_cast<std::chrono::system_clock::duration>(
      t - fs::file_time_type::clock::now() + std::chrono::system_clock::now());
  return std::chrono::duration_cast<std::chrono::seconds>(system.time_since_epoch()).count();
}

// What changes when a map is written: its files' sizes and times.
std::string Signature(const std::vector<fs::path>& files, int64_t* newest_unix_s) {
  std::ostringstream s;
  *newest_unix_s = 0;
  for (const auto& f : files) {
    std::error_code ec;
    const auto size = fs::file_size(f, ec);
    if (ec) continue;
    const auto time = fs::last_write_time(f, ec);
    if (ec) continue;
    s << f.filename().string() << ":" << size << ":" << time.time_since_epoch().count() << ";";
    *newest_unix_s = std::max(*newest_unix_s, UnixSeconds(time));
  }
  return s.str();
}

std::vector<double> Numbers(const std::string& text) {
  std::vector<double> out;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');) {
    try {
      out.push_back(std::stod(part));
    } catch (const std::exception&) {
      return {};
    }
  }
  return out;
}

void Read(CatalogEntry* e) {
  try {
    auto store = OpenExistingMap(e->path, /*writable=*/false);
    const auto meta = store->Metadata();
    auto get = [&](const std::string& k, const std::string& fallback) {
      auto it = meta.find(k);
      return it == meta.end() || it->second.empty() ? fallback : it->second;
    };
    e->name = get("name", e->name);
    const MissionMetadata mission = ReadMissionMetadata(meta);
    e->state = mission.state && !mission.state->empty() ? *mission.state : "complete";
    e->format = get("format", "png");
    const auto b = Numbers(get("bounds", ""));
    if (b.size() == 4) e->bounds = LatLonBounds{b[0], b[1], b[2], b[3]};
    e->min_zoom = std::atoi(get("minzoom", "0").c_str());
    e->max_zoom = std::atoi(get("maxzoom", "0").c_str());
    e->layers = mission.LayersOrRaw();
    const auto frames = store->Records().Frames();
    e->frames = static_cast<int64_t>(frames.size());
    for (const auto& f : frames) {
      if (!f.time_s) continue;
      e->first_time_s = std::min(e->first_time_s.value_or(*f.time_s), *f.time_s);
      e->last_time_s = std::max(e->last_time_s.value_or(*f.time_s), *f.time_s);
    }
    if (store->TileCount() == 0 && e->state == "complete") throw std::runtime_error("the map has no tiles");
    e->available = true;
  } catch (const std::exception& ex) {
    e->available = false;
    e->reason = ex.what();
  }
}

}  // namespace

std::string CatalogId(const std::string& file_name) {
  std::string stem = fs::path(file_name).stem().string(), id;
  for (char c : stem) {
    const char l = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (std::isalnum(static_cast<unsigned char>(l)) || l == '_')
      id += l;
    else if (!id.empty() && id.back() != '-')
      id += '-';
  }
  while (!id.empty() && id.back() == '-') id.pop_back();
  return id.empty() ? "map" : id;
}

MapCatalog::MapCatalog(std::string folder) : folder_(std::move(folder)) {
  std::error_code ec;
  if (!fs::is_directory(folder_, ec)) throw InputError(folder_, 0, "", "is not a folder of maps");
}

std::vector<CatalogEntry> MapCatalog::Scan() {
  std::vector<fs::path> maps;
  std::error_code ec;
  for (fs::directory_iterator it(folder_, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path p = it->path();
    std::error_code e2;
    if (p.extension() == ".mbtiles" && fs::is_regular_file(p, e2))
      maps.push_back(p);
    else if (fs::is_directory(p, e2) && fs::is_regular_file(p / "metadata.json", e2))
      maps.push_back(p);
  }
  if (ec) throw InputError(folder_, 0, "", "cannot be read: " + ec.message());
  std::sort(maps.begin(), maps.end());

  std::map<std::string, Seen> now;
  std::set<std::string> ids;
  std::vector<CatalogEntry> out;
  for (const auto& p : maps) {
    const bool mbtiles = p.extension() == ".mbtiles";
    int64_t modified = 0;
    const std::string signature = mbtiles ? Signature({p, fs::path(p.string() + "-wal")}, &modified)
                                          : Signature({p / "metadata.json"}, &modified);
    auto old = seen_.find(p.string());
    Seen seen;
    if (old != seen_.end() && old->second.signature == signature) {
      seen = old->second;
    } else {
      seen.signature = signature;
      seen.entry.path = p.string();
      seen.entry.name = p.filename().string();
      seen.entry.modified_unix_s = modified;
      Read(&seen.entry);
    }
    // A build in progress holds the map's lock; without it the build was
    // interrupted (asked at every scan: a killed build changes no file).
    if (seen.entry.state == "building" || seen.entry.state == "interrupted")
      seen.entry.state = MapLock::Holder(p.string()) ? "building" : "interrupted";
    // Ids follow the sorted paths, so they stay stable while files are added
    // with other names; a clash gets -2, -3...
    std::string id = CatalogId(p.filename().string());
    for (int n = 2; ids.count(id); ++n) id = CatalogId(p.filename().string()) + "-" + std::to_string(n);
    ids.insert(id);
    seen.entry.id = id;
    out.push_back(seen.entry);
    now[p.string()] = std::move(seen);
  }
  seen_ = std::move(now);
  std::sort(out.begin(), out.end(), [](const CatalogEntry& a, const CatalogEntry& b) { return a.id < b.id; });
  return out;
}

}  // namespace seamap
