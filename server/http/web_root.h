#pragma once
// The console's folder as the server may serve it: a request path names a
// file only where that file, every symbolic link resolved, lies inside the
// folder. A link inside web/ that leads to another file of web/ is served;
// one that leads out of it (to /etc, to the mission's photos...) is not
// (nginx's `disable_symlinks` refuses all links; links inside are harmless).
#include <filesystem>
#include <string_view>

namespace seamap::server {

class WebRoot {
 public:
  // `dir`: the --web folder (itself possibly a link: it is resolved once).
  explicit WebRoot(const std::filesystem::path& dir);

  // May the file a GET of `request_path` (decoded, as httplib's static file
  // handler joins it to the folder: "/" gets index.html) be served? False
  // when it resolves outside the folder; true when it is inside or does not
  // exist (the file handler then answers 404 itself).
  bool MayServe(std::string_view request_path) const;

 private:
  std::filesystem::path root_;  // canonical
};

}  // namespace seamap::server
