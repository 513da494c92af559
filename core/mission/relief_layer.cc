#include "core/mission/relief_layer.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/geo/local_frame.h"
#include "core/geo/web_mercator.h"
#include "core/mission/mission_metadata.h"
#include "core/terrain/height_datum.h"
#include "core/terrain/relief_shading.h"
#include "core/tiles/tile_codec.h"
#include "core/util/error.h"
#include "core/util/progress.h"

namespace seamap {
namespace {

std::optional<int> MetadataInt(const std::map<std::string, std::string>& m, const char* key) {
  auto it = m.find(key);
  if (it == m.end()) return std::nullopt;
  try {
    return std::stoi(it->second);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

// The grid's extent (cell edges) in lat/lon.
LatLonBounds GridBounds(const HeightGrid& g, const LocalFrame& frame) {
  const double w = g.east0_m - 0.5 * g.cell_m, e = g.east0_m + (g.cols() - 0.5) * g.cell_m;
  const double n = g.north0_m + 0.5 * g.cell_m, s = g.north0_m - (g.rows() - 0.5) * g.cell_m;
  LatLonBounds b{180, 90, -180, -90};
  for (const LocalXY& p : {LocalXY{w, n}, LocalXY{e, n}, LocalXY{e, s}, LocalXY{w, s}, LocalXY{0.5 * (w + e), n},
                           LocalXY{0.5 * (w + e), s}, LocalXY{w, 0.5 * (n + s)}, LocalXY{e, 0.5 * (n + s)}}) {
    const LatLon ll = frame.ToLatLon(p);
    b.west = std::min(b.west, ll.lon);
    b.east = std::max(b.east, ll.lon);
    b.south = std::min(b.south, ll.lat);
    b.north = std::max(b.north, ll.lat);
  }
  return b;
}

// The zoom whose pixels are no larger than half a cell.
int FinestUsefulZoom(const MissionTerrain& t, int tile_size) {
  int z = 0;
  while (z < 30 && MetersPerPixel(t.origin.lat, z, tile_size) > 0.5 * t.grid.cell_m) ++z;
  return z;
}

// One tile of the shaded cells: each pixel centre's local position
// (bilinear between the tile corners': a tile is affine to well under a
// pixel at the zooms that matter), then the cell image sampled bilinearly.
// Colours are un-premultiplied where a hole's transparent cell took part.
cv::Mat4b RenderTile(const TileId& id, int ts, const cv::Mat4b& shaded, const HeightGrid& g, const LocalFrame& frame) {
  LocalXY corner[4];  // NW, NE, SW, SE
  for (int k = 0; k < 4; ++k) {
    const GlobalPixel px{static_cast<double>(id.x + (k & 1)) * ts, static_cast<double>(id.y + (k >> 1)) * ts};
    corner[k] = frame.FromLatLon(PixelToLatLon(px, id.z, ts));
  }
  cv::Mat1f map_col(ts, ts), map_row(ts, ts);
  for (int j = 0; j < ts; ++j) {
    const double v = (j + 0.5) / ts;
    for (int i = 0; i < ts; ++i) {
      const double u = (i + 0.5) / ts;
      const double e = (1 - v) * ((1 - u) * corner[0].east + u * corner[1].east) +
                       v * ((1 - u) * corner[2].east + u * corner[3].east);
      const double n = (1 - v) * ((1 - u) * corner[0].north + u * corner[1].north) +
                       v * ((1 - u) * corner[2].north + u * corner[3].north);
      map_col(j, i) = static_cast<float>((e - g.east0_m) / g.cell_m);
      map_row(j, i) = static_cast<float>((g.north0_m - n) / g.cell_m);
    }
  }
  cv::Mat4b tile;
  cv::remap(shaded, tile, map_col, map_row, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(0, 0, 0, 0));
  for (int j = 0; j < ts; ++j)
    for (int i = 0; i < ts; ++i) {
      cv::Vec4b& p = tile(j, i);
      if (p[3] == 0 || p[3] == 255) continue;
      for (int k = 0; k < 3; ++k) p[k] = cv::saturate_cast<uint8_t>(p[k] * 255.0 / p[3]);
    }
  return tile;
}

bool AllTransparent(const cv::Mat4b& tile) {
  for (int j = 0; j < tile.rows; ++j)
    for (int i = 0; i < tile.cols; ++i)
      if (tile(j, i)[3] != 0) return false;
  return true;
}

}  // namespace

ReliefLayerOptions ReliefLayerOptionsFor(const TileStore& store, const MissionTerrain& terrain) {
  const auto metadata = store.Metadata();
  const MissionMetadata mission = ReadMissionMetadata(metadata);
  ReliefLayerOptions o;
  o.tile_size_px = mission.tile_size_px.value_or(256);
  auto format = metadata.find("format");
  if (format != metadata.end()) o.format = format->second;
  const int finest = FinestUsefulZoom(terrain, o.tile_size_px);
  o.max_zoom = MetadataInt(metadata, "maxzoom").value_or(finest);
  o.min_zoom = MetadataInt(metadata, "minzoom").value_or(std::max(0, finest - 6));
  return o;
}

nlohmann::json WriteReliefLayer(TileStore* store, const MissionTerrain& terrain, const ReliefLayerOptions& options,
                                bool show_progress) {
  const HeightGrid& g = terrain.grid;
  if (g.empty()) throw InputError("terrain", 0, "height_m", "the height model is empty");
  const int ts = options.tile_size_px;
  if (ts != 256 && ts != 512) throw InputError("terrain", 0, "tile_size", "expected 256 or 512");
  if (options.min_zoom < 0 || options.min_zoom > options.max_zoom || options.max_zoom > 30)
    throw InputError("terrain", 0, "zoom", "bad zoom range for the relief layer");
  TileEncoding encoding;
  encoding.format = ParseTileFormat(options.format, "terrain");
  const LocalFrame frame(terrain.origin);
  const ReliefStyle style = ReliefStyleFor(g);
  const cv::Mat4b shaded = ShadeRelief(g, style);
  const LatLonBounds bounds = GridBounds(g, frame);
  const int max_zoom = std::max(options.min_zoom, std::min(options.max_zoom, FinestUsefulZoom(terrain, ts)));

  struct Range {
    int z, x0, x1, y0, y1;
  };
  std::vector<Range> ranges;
  long total = 0;
  for (int z = options.min_zoom; z <= max_zoom; ++z) {
    const GlobalPixel nw = LatLonToPixel({bounds.north, bounds.west}, z, ts);
    const GlobalPixel se = LatLonToPixel({bounds.south, bounds.east}, z, ts);
    const int n = 1 << z;
    Range r{z, std::clamp(static_cast<int>(std::floor(nw.x / ts)), 0, n - 1),
            std::clamp(static_cast<int>(std::floor(se.x / ts)), 0, n - 1),
            std::clamp(static_cast<int>(std::floor(nw.y / ts)), 0, n - 1),
            std::clamp(static_cast<int>(std::floor(se.y / ts)), 0, n - 1)};
    total += static_cast<long>(r.x1 - r.x0 + 1) * (r.y1 - r.y0 + 1);
    ranges.push_back(r);
  }
  std::unique_ptr<TileStore> layer = store->OpenLayer(kReliefLayer);
  ProgressBar progress("relief tiles", total, show_progress);
  long done = 0, written = 0;
  for (const Range& r : ranges)
    for (int x = r.x0; x <= r.x1; ++x)
      for (int y = r.y0; y <= r.y1; ++y) {
        const TileId id{r.z, x, y};
        const cv::Mat4b tile = RenderTile(id, ts, shaded, g, frame);
        if (!AllTransparent(tile)) {
          layer->PutTile(id, EncodeTile(tile, encoding));
          ++written;
        }
        progress.Update(++done);
      }
  progress.Finish("tiles " + std::to_string(written));

  layer->SetMetadata("name", "relief");
  layer->SetMetadata("description", "Seabed relief (colour by height, hillshade) from SeaMap's height model");
  layer->SetMetadata("format", TileExtension(encoding.format));
  layer->SetMetadata("type", "overlay");
  layer->SetMetadata("minzoom", std::to_string(options.min_zoom));
  layer->SetMetadata("maxzoom", std::to_string(max_zoom));
  char text[128];
  std::snprintf(text, sizeof text, "%.8f,%.8f,%.8f,%.8f", bounds.west, bounds.south, bounds.east, bounds.north);
  layer->SetMetadata("bounds", text);

  const HeightDatum datum = UserDatum(g);
  nlohmann::json relief = {
      {"layer", kReliefLayer}, {"low_m", style.low_m + datum.offset_m}, {"high_m", style.high_m + datum.offset_m},
      {"datum", datum.name},   {"minzoom", options.min_zoom},           {"maxzoom", max_zoom},
      {"tiles", written}};
  MissionMetadata m;
  m.relief = relief;
  WriteMissionMetadata(store, m);
  return relief;
}

void StoreMissionTerrain(TileStore* store, const MissionTerrain& terrain, bool show_progress) {
  WriteMissionTerrain(store, terrain);
  WriteReliefLayer(store, terrain, ReliefLayerOptionsFor(*store, terrain), show_progress);
  store->Flush();
}

}  // namespace seamap
