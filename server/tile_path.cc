#include "server/tile_path.h"

#include <array>
#include <cstdint>

#include "server/api_error.h"

namespace seamap::server {
namespace {

// A non-negative decimal of at most 10 digits (the range is checked after).
bool ParseNumber(std::string_view s, int64_t* out) {
  if (s.empty() || s.size() > 10) return false;
  int64_t v = 0;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
    v = v * 10 + (c - '0');
  }
  *out = v;
  return true;
}

}  // namespace

TilePath ParseTilePath(std::string_view path) {
  // Split on '/' without allocating: tiles are the hot path.
  std::array<std::string_view, 4> parts;
  size_t count = 0;
  while (true) {
    const size_t slash = path.find('/');
    if (count == parts.size())
      throw ApiError(400, "tile path: expected /tiles/{z}/{x}/{y}.{ext} or /tiles/{layer}/{z}/{x}/{y}.{ext}");
    parts[count++] = path.substr(0, slash);
    if (slash == std::string_view::npos) break;
    path.remove_prefix(slash + 1);  // "z/x/y.png/" leaves an empty last part: not a tile
  }
  if (count != 3 && count != 4)
    throw ApiError(400, "tile path: expected /tiles/{z}/{x}/{y}.{ext} or /tiles/{layer}/{z}/{x}/{y}.{ext}");
  TilePath t;
  const std::string_view* zxy = parts.data();
  if (count == 4) {
    if (parts[0].empty()) throw ApiError(400, "tile path: empty layer name (\"/tiles//...\")");
    t.layer = std::string(parts[0]);
    ++zxy;
  }
  const size_t dot = zxy[2].find('.');
  if (dot == std::string_view::npos) throw ApiError(400, "tile path: expected {y}.{ext}, e.g. 12.png");
  t.ext = std::string(zxy[2].substr(dot + 1));
  const std::array<std::string_view, 3> numbers = {zxy[0], zxy[1], zxy[2].substr(0, dot)};
  int64_t v[3];
  for (int i = 0; i < 3; ++i)
    if (!ParseNumber(numbers[i], &v[i]))
      throw ApiError(400, "tile path: z, x and y must be non-negative integers, got '" + std::string(numbers[i]) + "'");
  if (v[0] > 30) throw ApiError(400, "tile path: zoom " + std::to_string(v[0]) + " is out of range 0..30");
  const int64_t n = int64_t{1} << v[0];
  if (v[1] >= n || v[2] >= n)
    throw ApiError(400,
                   "tile path: x and y must be below 2^z = " + std::to_string(n) + " at zoom " + std::to_string(v[0]));
  t.id = TileId{static_cast<int>(v[0]), static_cast<int>(v[1]), static_cast<int>(v[2])};
  return t;
}

}  // namespace seamap::server
