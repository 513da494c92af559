#include "server/tile_answer.h"

#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "server/api_error.h"
#include "server/http_server.h"

namespace seamap::server {
namespace {

std::string MimeForExtension(const std::string& ext) {
  if (ext == "png") return "image/png";
  if (ext == "jpg" || ext == "jpeg") return "image/jpeg";
  if (ext == "webp") return "image/webp";
  return "application/octet-stream";
}

TileAnswer Error(int status, const std::string& message) {
  TileAnswer a;
  a.status = status;
  a.content_type = "application/json";
  a.body = std::make_shared<const std::string>(nlohmann::json{{"error", message}}.dump());
  return a;
}

}  // namespace

bool EtagMatches(const std::string& header, const std::string& etag) {
  if (header == "*") return true;
  std::stringstream in(header);
  std::string part;
  while (std::getline(in, part, ',')) {
    size_t a = part.find_first_not_of(' ');
    size_t b = part.find_last_not_of(' ');
    if (a == std::string::npos) continue;
    std::string t = part.substr(a, b - a + 1);
    if (t.rfind("W/", 0) == 0) t = t.substr(2);  // weak comparison is fine for GET
    if (t == etag) return true;
  }
  return false;
}

TileAnswer AnswerTile(TileSource& tiles, bool building, const std::string& path,
                      const std::optional<std::string>& if_none_match) {
  try {
    TilePath t = ParseTilePath(path);
    const std::string format = tiles.Format();
    const bool same = t.ext == format || (format == "jpg" && t.ext == "jpeg");
    if (!same) return Error(404, "this mission's tiles are ." + format + ", not ." + t.ext);
    std::optional<Tile> tile;
    try {
      tile = tiles.Get(t.layer, t.id);
    } catch (const std::out_of_range&) {
      return Error(404, "no layer '" + t.layer + "'");
    }
    TileAnswer a;
    a.headers.push_back({"Access-Control-Allow-Origin", "*"});
    // A growing map: keep the tile, but ask (cheaply, 304) before reusing it.
    a.headers.push_back({"Cache-Control", building ? "no-cache" : "public, max-age=300"});
    if (!tile) {
      a.status = 204;
      return a;
    }
    a.headers.push_back({"ETag", tile->etag});
    if (if_none_match && EtagMatches(*if_none_match, tile->etag)) {
      a.status = 304;
      return a;
    }
    a.content_type = MimeForExtension(format);
    a.body = tile->bytes;
    return a;
  } catch (const ApiError& e) {
    return Error(e.status(), e.what());
  } catch (const std::exception& e) {
    return Error(500, e.what());
  }
}

}  // namespace seamap::server
