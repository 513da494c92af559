#pragma once
// The tile a request path names: "z/x/y.ext" or "layer/z/x/y.ext" (what
// follows "/tiles/"). Shared by both ways a tile request arrives.
#include <string>
#include <string_view>

#include "core/geo/web_mercator.h"

namespace seamap::server {

struct TilePath {
  std::string layer;  // empty: the main map
  TileId id;
  std::string ext;  // as asked for, e.g. "png"; checked against the mission's format by the caller
};

// Throws ApiError(400) naming what is wrong when the path is malformed or the
// tile is out of range (zoom 0..30, x and y below 2^z).
TilePath ParseTilePath(std::string_view path);

}  // namespace seamap::server
