#include "server/mission_registry.h"

#include <cstdio>
#include <filesystem>

#include "core/mission/map_follower.h"
#include "core/mission/mission_metadata.h"
#include "server/api_error.h"
#include "server/track_feature.h"

namespace seamap::server {

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
    for (const TrackPoint& t : mission.TrackFrom(track_before)) events.Publish("track", TrackPointJson(t).dump());
    const auto status = mission.StatusJson();
    if (!status["last_pose"].is_null()) events.Publish("pose", status["last_pose"].dump());
    events.Publish("progress", status.dump());
  }

  std::string path;
  MapFollower follower;
  const TileStore& records;
  MissionState& mission;
  EventHub& events;
  DetectionRegistry& detections;
  TileSource& tiles;
};

struct MissionRegistry::OpenMission {
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

MissionRegistry::MissionRegistry(std::string folder, bool token_required)
    : token_required_(token_required), catalog_(std::make_unique<MapCatalog>(std::move(folder))) {}

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
  std::lock_guard<std::mutex> lock(mutex_);
  listing_ = std::move(listing);
  scanned_ = std::chrono::steady_clock::now();
  scanning_ = false;
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
      it->second->SetExternalWriter(e.state == "building");  // tiles still change: short cache
      return {e, it->second};
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
      it->second->SetExternalWriter(e.state == "building");
      return {e, it->second};
    }
  }
  auto made = std::make_shared<TileSource>(path, 4, 16u << 20);
  std::lock_guard<std::mutex> lock(mutex_);
  const CatalogEntry& e = EntryLocked(id);
  std::shared_ptr<TileSource>& source = sources_[e.path];
  if (!source) source = std::move(made);
  source->SetExternalWriter(e.state == "building");
  return {e, source};
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
        source = it->second;
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
    return {root_mission_, root_detections_, root_events_};
  }
  auto [entry, tiles] = Entry(id);  // 404 for an unknown or unavailable id
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = open_.find(entry.path);
    if (it != open_.end()) return {&it->second->mission, it->second->detections.get(), &it->second->events};
  }
  // Opened outside mutex_ (SQLite reads), one opening at a time.
  std::lock_guard<std::mutex> opening(opening_);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = open_.find(entry.path);
    if (it != open_.end()) return {&it->second->mission, it->second->detections.get(), &it->second->events};
  }
  auto m = std::make_unique<OpenMission>();
  try {
    m->records = OpenExistingMap(entry.path, /*writable=*/false);
    m->mission.Load(*m->records);
    m->detections = std::make_unique<DetectionRegistry>(nullptr, &m->events);  // a catalogue is read-only
    m->detections->Load(*m->records);
    // The dive's file name where the map has only the default name.
    m->mission.SetName(entry.name == "seamap mission" ? std::filesystem::path(entry.path).stem().string() : entry.name);
    m->mission.SetLayers(tiles->Layers(), tiles->Format());
    m->mission.SetAccess(token_required_, false);
    m->followed = std::make_unique<Followed>(entry.path, *m->records, m->mission, m->events, *m->detections, *tiles);
    m->followed->Step();  // its state as the file tells it now
  } catch (const std::exception& e) {
    throw ApiError(404, "mission '" + id + "' cannot be read: " + e.what());
  }
  std::lock_guard<std::mutex> lock(mutex_);
  std::unique_ptr<OpenMission>& open = open_[entry.path];
  if (!open) open = std::move(m);
  return {&open->mission, open->detections.get(), &open->events};
}

void MissionRegistry::FollowMap(const std::string& path, const TileStore& records) {
  root_ = std::make_unique<Followed>(path, records, *root_mission_, *root_events_, *root_detections_, *root_tiles_);
  root_->Step();
}

void MissionRegistry::Follow() {
  std::vector<Followed*> follow;
  if (root_) follow.push_back(root_.get());
  if (catalog_) {
    try {
      Refresh();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "warning: cannot list %s: %s\n", catalog_->folder().c_str(), e.what());
    }
    // Which open missions to follow, under the lock; their files are read outside
    // it, so tile requests do not wait on SQLite (open missions are never closed).
    std::lock_guard<std::mutex> lock(mutex_);
    for (const CatalogEntry& e : listing_) {
      auto it = open_.find(e.path);
      if (it != open_.end() && e.available) follow.push_back(it->second->followed.get());
    }
  }
  for (Followed* f : follow) {
    try {
      f->Step();
      f->detections.Refresh(f->records);  // another process's stereo-locate --map or detect
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
