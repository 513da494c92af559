#include "server/tile_answer.h"

#include <algorithm>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "server/api_error.h"
#include "server/tile_path.h"

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

bool EtagMatches(std::string_view header, std::string_view etag) {
  if (header == "*") return true;
  while (!header.empty()) {
    const size_t comma = std::min(header.find(','), header.size());
    std::string_view t = header.substr(0, comma);
    header.remove_prefix(std::min(comma + 1, header.size()));
    while (!t.empty() && (t.front() == ' ' || t.front() == '\t')) t.remove_prefix(1);
    while (!t.empty() && (t.back() == ' ' || t.back() == '\t')) t.remove_suffix(1);
    if (t.substr(0, 2) == "W/") t.remove_prefix(2);  // weak comparison is fine for GET
    if (t == etag) return true;
  }
  return false;
}

TileAnswer AnswerTile(TileSource& tiles, bool building, std::string_view path,
                      const std::optional<std::string>& if_none_match) {
  try {
    TilePath t = ParseTilePath(path);
    const std::string format = tiles.Format();
    const bool same = t.ext == format || (format == "jpg" && t.ext == "jpeg");
    bool transcoded = false;
    if (!same) {  // the formats offered only when another is asked for: not on every tile
      const auto offered = tiles.Formats();
      transcoded = std::find(offered.begin(), offered.end(), t.ext) != offered.end();
      if (!transcoded) {
        std::string names;
        for (const auto& f : offered) names += (names.empty() ? "." : " or .") + f;
        return Error(404, "this mission's tiles are " + names + ", not ." + t.ext);
      }
    }
    std::optional<Tile> tile;
    try {
      tile = transcoded ? tiles.GetAs(t.layer, t.id, t.ext) : tiles.Get(t.layer, t.id);
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
    a.content_type = MimeForExtension(transcoded ? t.ext : format);
    a.body = tile->bytes;
    return a;
  } catch (const ApiError& e) {
    return Error(e.status(), e.what());
  } catch (const std::exception& e) {
    return Error(500, e.what());
  }
}

}  // namespace seamap::server
