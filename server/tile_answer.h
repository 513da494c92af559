#pragma once
// The answer to a tile request, independent of the HTTP library that sends
// it: httplib's handler and the event-driven tile front end both use it, so
// tiles are answered the same way whichever path a connection took.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "server/tile_source.h"

namespace seamap::server {

struct TileAnswer {
  int status = 200;
  std::string content_type;                 // of body; empty without one
  std::shared_ptr<const std::string> body;  // tile bytes or a JSON error; null for 204/304
  // Extra headers: ETag, Cache-Control, Access-Control-Allow-Origin.
  std::vector<std::pair<std::string, std::string>> headers;
};

// `path` is what follows "/tiles/" ("z/x/y.ext" or "layer/z/x/y.ext").
// `building`: the map is still growing (browsers must revalidate).
TileAnswer AnswerTile(TileSource& tiles, bool building, std::string_view path,
                      const std::optional<std::string>& if_none_match);

// Does an If-None-Match header list this ETag (or "*")?
bool EtagMatches(std::string_view header, std::string_view etag);

}  // namespace seamap::server
