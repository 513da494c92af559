#pragma once
// Original photos for the browser: the file's own bytes when a browser can
// show it, else (TIFF, 16-bit, ...) converted to PNG; or a JPEG scaled to fit
// a box, for thumbnails. A mission's records say where its photos are, and a
// mission file can say anything (issue 33): a photo is served only from the
// mission's own photo folder or the server's --images folder (symlinks
// resolved, none out), only a regular file (a FIFO would hold a thread for
// ever), at most kMaxPhotoBytes, read within kPhotoReadTimeout, and only when
// its bytes are an image of the type its name says.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "core/tiles/mission_records.h"

namespace seamap::server {

constexpr int64_t kMaxPhotoBytes = int64_t{256} << 20;
constexpr auto kPhotoReadTimeout = std::chrono::seconds(10);

struct Photo {
  std::string bytes;
  std::string content_type;
};

// The folder a frame's photo was read from: its recorded path less the
// navigation's file name ("survey/photo/a/1.png" less "a/1.png"), else the
// recorded path's folder. Lexical: nothing is read.
std::string PhotoFolderOf(const FrameRecord& frame);

// Inside which folders a mission's photos may be: `mission_folder` (the one
// most of its frames were read from, MissionState::PhotoFolder) and
// `photo_dir` (the server's --images, where photos whose recorded path is
// gone are looked up by name); either may be empty.
struct PhotoFolders {
  std::string mission_folder;
  std::string photo_dir;
};

// The file to serve for `frame`: its recorded path when it resolves inside
// one of the folders, else --images/IMAGE when that resolves inside
// --images. nullopt, and *problem says why, otherwise.
std::optional<std::string> ResolvePhoto(const FrameRecord& frame, const PhotoFolders& folders, std::string* problem);

// The photo at `path` (from ResolvePhoto). `max_side` 0: full size. nullopt,
// and *problem says why, when it is not a regular file, too large, too slow
// to read, not the image its name says, or cannot be decoded.
std::optional<Photo> LoadPhoto(const std::string& path, int max_side, std::string* problem);

// At most `slots` photos loaded at once, so photo requests can never take
// every server thread (the API and tiles keep answering).
class PhotoGate {
 public:
  explicit PhotoGate(int slots) : free_(slots) {}
  // Takes a slot, waiting at most `wait`; false when none came free.
  bool Enter(std::chrono::milliseconds wait);
  void Leave();

 private:
  std::mutex mutex_;
  std::condition_variable freed_;
  int free_;
};

}  // namespace seamap::server
