#include "server/mission_registry.h"

#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "core/mission/map_follower.h"
#include "core/mission/mission_metadata.h"
#include "server/api_error.h"
#include "server/http/http_util.h"
#include "server/track_feature.h"

namespace seamap::server {

namespace {

// How the files a map's records live in look now (inode, size, modification
// time of the file, its WAL, a folder's detections.json): while it is the
// same, no other process wrote, and the detections need not be read again
// (232,362 of them took seconds and hundreds of MB every two seconds).
std::string RecordsStamp(const std::string& path) {
  std::string out;
  for (const std::string& file : {path, path + "-wal", (std::filesystem::path(path) / "detections.json").string()}) {
    struct stat st {};
    if (::stat(file.c_str(), &st) != 0) {
      out += "-;";
      continue;
    }
    out += std::to_string(st.st_ino) + ":" + std::to_string(st.st_size) + ":" + std::to_string(st.st_mtim.tv_sec) +
           "." + std::to_string(st.st_mtim.tv_nsec) + ";";
  }
  return out;
}

}  // namespace

// A map followed from its file, and where what changes goes.
struct MissionRegistry::Followed {
  Followed(std::string map_path, const TileStore& map_records, MissionState& m, EventHub& e, DetectionRegistry& d,
           TileSource& t)
      : path(std::move(map_path)),
        follower(path,
                 [source = &t] {  // through the tile source, which re-reads the metadata of a map being written
                   return ReadMissionMetadata(source->Metadata("")).StateOrEmpty();
                 }),
        records(map_records),
        mission(m),
        events(e),
        detections(d),
        tiles(t) {}

  // One look at the file: the state, and the records when it is being built
  // (or just stopped being), published as `track`, `pose` and `progress`.
  void Step() {
    const MapFollowStep step = follower.Step(records);
    if (step.state_changed) {
      Progress p = mission.progress();
      // Loading the records gave complete or stopped; building and interrupted only the file's lock tells.
      if (step.build.state == "building" || step.build.state == "interrupted") p.state = step.build.state;
      p.state_detail = step.state_detail;
      mission.SetProgress(p);
      tiles.SetExternalWriter(step.being_written);
      if (step.build.state == "interrupted")
        std::fprintf(stderr, "seamap serve: %s: %s\n", path.c_str(), step.state_detail.c_str());
    }
    if (!step.reload_records) return;
    const int track_before = mission.TrackSize();
    mission.Load(records);
    Progress p = mission.progress();
    p.state = step.state;
    p.state_detail = step.state_detail;
    mission.SetProgress(p);
    for (const TrackPoint& t : mission.TrackFrom(track_before)) events.Publish("track", Dump(TrackPointJson(t)));
    const auto status = mission.StatusJson();
    if (!status["last_pose"].is_null()) events.Publish("pose", Dump(status["last_pose"]));
    events.Publish("progress", Dump(status));  // a name need not be UTF-8
  }

  // Takes in the detections another process stored (stereo-locate --map,
  // detect), when the map's files changed since the last look.
  void RefreshDetections() {
    const std::string stamp = RecordsStamp(path);
    if (stamp == detections_stamp) return;
    detections.Refresh(records);
    detections_stamp = stamp;
  }

  std::string path;
  std::string detections_stamp;  // RecordsStamp when the detections were last read; empty: never
  MapFollower follower;
  const TileStore& records;
  MissionState& mission;
  EventHub& events;
  DetectionRegistry& detections;
  TileSource& tiles;
};

struct MissionRegistry::OpenMission {
  std::shared_ptr<TileSource> tiles;  // the follower reads the map's state through it
  MapFileStamp stamp;                 // the file as it was opened
  std::unique_ptr<TileStore> records;
  MissionState mission;
  EventHub events;
  std::unique_ptr<DetectionRegistry> detections;
  std::unique_ptr<Followed> followed;
};

MissionRegistry::MissionRegistry(TileSource* tiles, MissionState* mission, DetectionRegistry* detections,
                                 EventHub* events, bool token_required)
    : token_required_(token_required),
      root_tiles_(tiles),
      root_mission_(mission),
      root_detections_(detections),
      root_events_(events) {
  root_mission_->SetAccess(token_required_, root_detections_->writable());
}

MissionRegistry::MissionRegistry(std::string folder, bool token_required, size_t max_open)
    : token_required_(token_required),
      max_open_(std::max<size_t>(1, max_open)),
      catalog_(std::make_unique<MapCatalog>(std::move(folder))) {}

std::optional<MapFileStamp> StampOf(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return std::nullopt;
  if (S_ISDIR(st.st_mode) && ::stat((std::filesystem::path(path) / "metadata.json").c_str(), &st) != 0)
    return std::nullopt;
  MapFileStamp stamp;
  stamp.device = static_cast<uint64_t>(st.st_dev);
  stamp.inode = static_cast<uint64_t>(st.st_ino);
  stamp.size = static_cast<int64_t>(st.st_size);
  stamp.modified_ns = int64_t{st.st_mtim.tv_sec} * 1000000000 + st.st_mtim.tv_nsec;
  return stamp;
}

MissionRegistry::~MissionRegistry() = default;

void MissionRegistry::Refresh() {
  if (!catalog_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool fresh = scanned_ != std::chrono::steady_clock::time_point{} &&
                       std::chrono::steady_clock::now() - scanned_ <= std::chrono::seconds(1);
    if (fresh || scanning_) return;  // one thread rescans; the others use the listing they have
    scanning_ = true;
  }
  std::vector<CatalogEntry> listing;
  try {
    listing = catalog_->Scan();  // outside mutex_: tile requests do not wait on the folder
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    scanning_ = false;
    throw;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    listing_ = std::move(listing);
    scanned_ = std::chrono::steady_clock::now();
    scanning_ = false;
  }
  CloseChanged();
}

void MissionRegistry::CloseChanged() {
  struct Opened {
    std::string path;
    MapFileStamp stamp;
    bool building = false, listed = false;
  };
  std::vector<Opened> opened;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [path, open] : sources_) {
      Opened o{path, open.stamp};
      for (const CatalogEntry& e : listing_)
        if (e.path == path) {
          o.listed = e.available;
          o.building = e.state == "building";
        }
      opened.push_back(o);
    }
  }
  std::vector<std::string> changed;
  for (const Opened& o : opened) {  // stat outside mutex_: tile requests do not wait on the disk
    const std::optional<MapFileStamp> now = o.listed ? StampOf(o.path) : std::nullopt;
    // Another file moved over it, or it is gone: always. Rewritten in place:
    // unless it is being built (then it changes all the time, and its follower reads it).
    const bool replaced = !now || now->device != o.stamp.device || now->inode != o.stamp.inode;
    if (replaced || (!o.building && !(*now == o.stamp))) changed.push_back(o.path);
  }
  if (changed.empty()) return;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const std::string& path : changed) {
    auto it = sources_.find(path);
    const Opened* o = nullptr;
    for (const Opened& x : opened)
      if (x.path == path) o = &x;
    if (it == sources_.end() || !o || !(it->second.stamp == o->stamp)) continue;  // reopened meanwhile
    std::fprintf(stderr, "seamap serve: %s changed on disk: opened again at its next request\n", path.c_str());
    CloseLocked(path);
  }
}

void MissionRegistry::CloseLocked(const std::string& path) {
  sources_.erase(path);  // requests in flight keep their shared_ptr
  auto it = open_.find(path);
  if (it == open_.end()) return;
  it->second->events.Close();  // its streams end; browsers reconnect to the map opened again
  open_.erase(it);
}

void MissionRegistry::EvictLocked() {
  while (sources_.size() > max_open_) {
    auto oldest = sources_.begin();
    for (auto it = sources_.begin(); it != sources_.end(); ++it)
      if (it->second.used < oldest->second.used) oldest = it;
    CloseLocked(std::string(oldest->first));
  }
}

std::vector<CatalogEntry> MissionRegistry::Missions() {
  Refresh();
  std::lock_guard<std::mutex> lock(mutex_);
  return listing_;
}

const CatalogEntry& MissionRegistry::EntryLocked(const std::string& id) {
  for (const CatalogEntry& e : listing_) {
    if (e.id != id) continue;
    if (!e.available) throw ApiError(404, "mission '" + id + "' is unavailable: " + e.reason);
    return e;
  }
  throw ApiError(404, "no mission '" + id + "' in " + catalog_->folder());
}

std::pair<CatalogEntry, std::shared_ptr<TileSource>> MissionRegistry::Entry(const std::string& id) {
  Refresh();
  std::string path;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const CatalogEntry& e = EntryLocked(id);
    auto it = sources_.find(e.path);
    if (it != sources_.end()) {
      it->second.used = ++use_clock_;
      it->second.source->SetExternalWriter(e.state == "building");  // tiles still change: short cache
      return {e, it->second.source};
    }
    path = e.path;
  }
  // A new source opens its SQLite connections outside mutex_, one opening at a
  // time: whoever waited finds it made.
  std::lock_guard<std::mutex> opening(opening_);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = sources_.find(path);
    if (it != sources_.end()) {
      const CatalogEntry& e = EntryLocked(id);
      it->second.used = ++use_clock_;
      it->second.source->SetExternalWriter(e.state == "building");
      return {e, it->second.source};
    }
  }
  // The stamp before opening: a file moved over it meanwhile is seen as a change.
  const std::optional<MapFileStamp> stamp = StampOf(path);
  if (!stamp) throw ApiError(404, "mission '" + id + "' is gone: " + path);
  auto made = std::make_shared<TileSource>(path, 4, 16u << 20);
  std::lock_guard<std::mutex> lock(mutex_);
  const CatalogEntry& e = EntryLocked(id);
  OpenSource& open = sources_[e.path];
  if (!open.source) {
    open.source = std::move(made);
    open.stamp = *stamp;
  }
  open.used = ++use_clock_;
  std::shared_ptr<TileSource> source = open.source;
  source->SetExternalWriter(e.state == "building");
  const CatalogEntry entry = e;
  EvictLocked();
  return {entry, source};
}

MissionTiles MissionRegistry::Tiles(const std::string& id) {
  if (!catalog_) {
    if (!id.empty()) throw ApiError(404, "no mission '" + id + "'");
    // Not owned: the caller's source outlives the server.
    return {std::shared_ptr<TileSource>(std::shared_ptr<void>(), root_tiles_), root_mission_->building(),
            "SeaMap mission"};
  }
  auto [entry, source] = Entry(id);
  return {std::move(source), entry.state == "building", entry.name};
}

std::optional<TileAnswer> MissionRegistry::AnswerMissionTile(const std::string& id, const std::string& path,
                                                             const std::optional<std::string>& if_none_match) {
  if (!catalog_) {  // the hot path of one map: no lock, no copy
    if (!id.empty()) return std::nullopt;
    return AnswerTile(*root_tiles_, root_mission_->building(), path, if_none_match);
  }
  if (id.empty()) return std::nullopt;
  std::shared_ptr<TileSource> source;
  bool building = false;
  try {
    Refresh();
    {
      std::lock_guard<std::mutex> lock(mutex_);  // a tile request copies no entry, only its source
      const CatalogEntry& e = EntryLocked(id);
      auto it = sources_.find(e.path);
      if (it != sources_.end()) {
        it->second.used = ++use_clock_;
        source = it->second.source;
        building = e.state == "building";
        source->SetExternalWriter(building);
      }
    }
    if (!source) {  // the mission's first tile request opens its source, here, once (Entry)
      auto [entry, made] = Entry(id);
      source = std::move(made);
      building = entry.state == "building";
    }
  } catch (const std::exception&) {
    return std::nullopt;  // unknown, unavailable or unreadable: the backend answers why
  }
  return AnswerTile(*source, building, path, if_none_match);
}

MissionServices MissionRegistry::Services(const std::string& id) {
  if (!catalog_) {
    if (!id.empty()) throw ApiError(404, "no mission '" + id + "'");
    return {root_mission_, root_detections_, root_events_, nullptr};
  }
  auto services = [](const std::shared_ptr<OpenMission>& m) {
    return MissionServices{&m->mission, m->detections.get(), &m->events, m};
  };
  auto [entry, tiles] = Entry(id);  // 404 for an unknown or unavailable id
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = open_.find(entry.path);
    if (it != open_.end()) return services(it->second);
  }
  // Opened outside mutex_ (SQLite reads), one opening at a time.
  std::lock_guard<std::mutex> opening(opening_);
  MapFileStamp stamp;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = open_.find(entry.path);
    if (it != open_.end()) return services(it->second);
    auto source = sources_.find(entry.path);
    if (source == sources_.end() || source->second.source != tiles)  // closed meanwhile (changed, or evicted)
      throw ApiError(503, "mission '" + id + "' changed while it was opened; ask again");
    stamp = source->second.stamp;
  }
  // Whatever its records hold, a mission that cannot be read answers this
  // error and is not kept: the other missions and the server go on.
  auto m = std::make_shared<OpenMission>();
  const std::string records_stamp = RecordsStamp(entry.path);  // before reading: a write meanwhile is seen later
  try {
    m->tiles = tiles;
    m->stamp = stamp;
    m->records = OpenExistingMap(entry.path, /*writable=*/false);
    m->mission.Load(*m->records);
    m->detections = std::make_unique<DetectionRegistry>(nullptr, &m->events);  // a catalogue is read-only
    m->detections->Load(*m->records);
    // The dive's file name where the map has only the default name.
    m->mission.SetName(entry.name == "seamap mission" ? std::filesystem::path(entry.path).stem().string() : entry.name);
    m->mission.SetLayers(tiles->Layers(), tiles->Format());
    m->mission.SetAccess(token_required_, false);
    m->followed = std::make_unique<Followed>(entry.path, *m->records, m->mission, m->events, *m->detections, *tiles);
    m->followed->detections_stamp = records_stamp;
    m->followed->Step();  // its state as the file tells it now
  } catch (const std::exception& e) {
    throw ApiError(404, "mission '" + id + "' cannot be read: " + e.what());
  }
  if (const int64_t n = m->detections->Unreadable(); n > 0)
    std::fprintf(stderr,
                 "warning: %s: %lld detection record(s) cannot be read (a number null or not finite): left out\n",
                 entry.path.c_str(), static_cast<long long>(n));
  std::lock_guard<std::mutex> lock(mutex_);
  auto source = sources_.find(entry.path);
  if (source == sources_.end() || source->second.source != tiles) return services(m);  // closed meanwhile: not kept
  std::shared_ptr<OpenMission>& open = open_[entry.path];
  if (!open) open = std::move(m);
  return services(open);
}

void MissionRegistry::FollowMap(const std::string& path, const TileStore& records) {
  root_ = std::make_unique<Followed>(path, records, *root_mission_, *root_events_, *root_detections_, *root_tiles_);
  root_->Step();
}

void MissionRegistry::Follow() {
  std::vector<Followed*> follow;
  std::vector<std::shared_ptr<OpenMission>> held;
  if (root_) follow.push_back(root_.get());
  if (catalog_) {
    try {
      Refresh();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "warning: cannot list %s: %s\n", catalog_->folder().c_str(), e.what());
    }
    // Which open missions to follow, under the lock; their files are read outside
    // it, so tile requests do not wait on SQLite (held here while they are read).
    std::lock_guard<std::mutex> lock(mutex_);
    for (const CatalogEntry& e : listing_) {
      auto it = open_.find(e.path);
      if (it == open_.end() || !e.available || !it->second || !it->second->followed) continue;
      held.push_back(it->second);
      follow.push_back(it->second->followed.get());
    }
  }
  for (Followed* f : follow) {
    try {
      f->Step();
      f->RefreshDetections();  // another process's stereo-locate --map or detect
    } catch (const std::exception& e) {
      std::fprintf(stderr, "warning: cannot follow %s: %s\n", f->path.c_str(), e.what());
    }
  }
}

void MissionRegistry::CloseEvents() {
  if (root_events_) root_events_->Close();
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto& [path, open] : open_) open->events.Close();
}

}  // namespace seamap::server
