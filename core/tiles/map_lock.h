#pragma once
// Who is writing a map: a building process holds an exclusive lock on the
// sidecar file MAP.lock (next to the .mbtiles file or the tile folder), and
// the kernel releases it when the process ends, however it ends (kill -9
// included). A map whose state says "building" while nobody holds the lock
// was interrupted (core/mission/build_state.h).
//
// Open file description locks (F_OFD_SETLK): readers test them without
// taking them (F_OFD_GETLK), so `seamap info` or `serve` never makes a
// starting build fail. The holder's pid is written into the file for messages.
#include <optional>
#include <string>

namespace seamap {

class MapLock {
 public:
  // Takes the lock of the map at `map_path`, creating MAP.lock. Throws
  // InputError(map_path, 0, param, ...) when another process holds it.
  static MapLock Acquire(const std::string& map_path, const std::string& param);
  // The pid of the process holding the map's lock (0 when unknown), or
  // nullopt when none does.
  static std::optional<int> Holder(const std::string& map_path);
  static std::string LockPath(const std::string& map_path);

  MapLock() = default;
  MapLock(MapLock&& other) noexcept;
  MapLock& operator=(MapLock&& other) noexcept;
  MapLock(const MapLock&) = delete;
  MapLock& operator=(const MapLock&) = delete;
  ~MapLock();  // removes MAP.lock and releases the lock

  bool held() const { return fd_ >= 0; }

 private:
  void Release();
  int fd_ = -1;
  std::string path_;
};

}  // namespace seamap
