#pragma once
// Original photos for the browser: the file's own bytes when a browser can
// show it, else (TIFF, 16-bit, ...) converted to PNG; or a JPEG scaled to fit
// a box, for thumbnails.
#include <optional>
#include <string>

namespace seamap::server {

struct Photo {
  std::string bytes;
  std::string content_type;
};

// nullopt when the file cannot be read or decoded. `max_side` 0: full size.
std::optional<Photo> LoadPhoto(const std::string& path, int max_side);

}  // namespace seamap::server
