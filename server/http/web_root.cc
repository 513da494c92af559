#include "server/http/web_root.h"

#include <string>
#include <system_error>

namespace seamap::server {

WebRoot::WebRoot(const std::filesystem::path& dir) {
  std::error_code ec;
  root_ = std::filesystem::canonical(dir, ec);
  if (ec) root_ = std::filesystem::absolute(dir, ec).lexically_normal();
}

bool WebRoot::MayServe(std::string_view request_path) const {
  std::string relative(request_path);
  while (!relative.empty() && relative.front() == '/') relative.erase(0, 1);
  if (relative.empty() || relative.back() == '/') relative += "index.html";
  std::error_code ec;
  const std::filesystem::path joined = root_ / relative;
  // A name that does not exist (or a link to nothing) is the file handler's 404.
  if (!std::filesystem::exists(std::filesystem::symlink_status(joined, ec))) return true;
  const std::filesystem::path real = std::filesystem::canonical(joined, ec);
  if (ec) return !std::filesystem::exists(joined, ec);  // a dangling link: nothing is read through it
  // Inside: the root is a prefix of the resolved path, component by component.
  auto r = root_.begin(), p = real.begin();
  for (; r != root_.end(); ++r, ++p)
    if (p == real.end() || *r != *p) return false;
  return true;
}

}  // namespace seamap::server
