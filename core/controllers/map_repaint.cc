#include "core/controllers/map_repaint.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/camera/frame_projector.h"
#include "core/mosaic/overview_pyramid.h"
#include "core/mosaic/tile_writer.h"
#include "core/util/thread_pool.h"

namespace seamap {
namespace {

// An offline build's buffer: tiles written once, when no frame to come is over them.
BuildConfig OfflineConfig(BuildConfig config) {
  config.buffer.live_tiles = false;
  return config;
}

}  // namespace

TileSet FrameTiles(const CameraModel& camera, const LocalFrame& frame, const VehiclePose& pose, int zoom,
                   int tile_size) {
  TileSet tiles;
  const auto corners = Footprint(camera, pose);
  if (!corners) return tiles;
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const auto& c : *corners) {
    const GlobalPixel p = LatLonToPixel(frame.ToLatLon(c), zoom, tile_size);
    x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  }
  // A footprint of thousands of tiles is no frame a survey paints (MosaicBuilder refuses it).
  if (!(x1 - x0 < 64.0 * tile_size && y1 - y0 < 64.0 * tile_size)) return tiles;
  for (int ty = static_cast<int>(std::floor(y0 / tile_size)); ty <= static_cast<int>(std::floor(y1 / tile_size)); ++ty)
    for (int tx = static_cast<int>(std::floor(x0 / tile_size)); tx <= static_cast<int>(std::floor(x1 / tile_size));
         ++tx)
      tiles.insert({zoom, tx, ty});
  return tiles;
}

RepaintResult RepaintWholeMap(TileStore* store, const RepaintSetup& setup, const std::vector<FrameSpec>& frames) {
  RepaintResult result;
  const TileSet before = [&] {
    const std::vector<TileId> ids = store->TileIds();
    return TileSet(ids.begin(), ids.end());
  }();
  RepaintStore fresh(store, {setup.plan.base_zoom, std::nullopt, true, true});
  {
    MosaicBuilder builder(OfflineConfig(setup.config), setup.camera, setup.frame, setup.plan, &fresh, setup.hooks);
    builder.Foresee(frames);  // every pose is known: tiles are written once
    for (const FrameSpec& f : frames) builder.Push(f);
    builder.Finish();
    result.frames_painted = builder.stats().frames_used;
  }
  const TileSet written = fresh.Written();
  for (const TileId& id : written) result.base_tiles += id.z == setup.plan.base_zoom;
  result.written = written;
  // What the old poses painted and the new ones do not: empty now.
  const int ts = setup.config.map.tile_size;
  const std::vector<uint8_t> empty =
      EncodeTile(cv::Mat::zeros(ts, ts, CV_8UC(setup.plan.channels + 1)), setup.config.map.encoding);
  for (const TileId& id : before)
    if (!written.count(id) && id.z >= setup.plan.min_zoom && id.z <= setup.plan.base_zoom) {
      store->PutTile(id, empty);
      result.written.insert(id);
      ++result.cleared;
    }
  store->Flush();
  return result;
}

RepaintResult RepaintTiles(TileStore* store, const RepaintSetup& setup, const std::vector<FrameSpec>& frames,
                           const TileSet& tiles) {
  RepaintResult result;
  if (tiles.empty()) return result;
  const int zoom = setup.plan.base_zoom, ts = setup.config.map.tile_size;
  // The frames over the tiles, and two on either side of each: the handover
  // partners that decide which of them paints a pixel.
  std::set<size_t> chosen;
  for (size_t i = 0; i < frames.size(); ++i) {
    const TileSet under = FrameTiles(setup.camera, setup.frame, frames[i].pose, zoom, ts);
    if (std::none_of(under.begin(), under.end(), [&](const TileId& t) { return tiles.count(t) > 0; })) continue;
    for (size_t k = i >= 2 ? i - 2 : 0; k <= std::min(frames.size() - 1, i + 2); ++k) chosen.insert(k);
  }
  std::vector<FrameSpec> subset;
  for (size_t i : chosen) subset.push_back(frames[i]);
  RepaintStore fresh(store, {zoom, tiles, false, false});
  {
    BuildHooks hooks;  // no records: the frames keep theirs
    hooks.preprocess = setup.hooks.preprocess;
    hooks.surface = setup.hooks.surface;
    MosaicBuilder builder(OfflineConfig(setup.config), setup.camera, setup.frame, setup.plan, &fresh, hooks);
    builder.Foresee(subset);
    for (const FrameSpec& f : subset) builder.Push(f);
    builder.Finish();
    result.frames_painted = builder.stats().frames_used;
  }
  TileSet changed = fresh.Written();
  result.base_tiles = changed.size();
  result.written = changed;
  // The overviews above them, each from its four children as the map holds them now.
  ThreadPool pool(1);
  TileWriter writer(store, &pool, setup.config.map.encoding);
  for (int z = zoom - 1; z >= setup.plan.min_zoom && !changed.empty(); --z) {
    TileSet parents;
    for (const TileId& c : changed) parents.insert(c.Parent());
    for (const TileId& p : parents) {
      cv::Mat parent = cv::Mat::zeros(ts, ts, CV_8UC(setup.plan.channels + 1));
      for (int q = 0; q < 4; ++q) {
        const TileId child{z + 1, 2 * p.x + (q & 1), 2 * p.y + (q >> 1)};
        const cv::Mat tile = writer.ReadToPaint(child, setup.plan.channels, ts);
        if (tile.empty()) continue;
        ReduceTile2x(tile).copyTo(parent(cv::Rect((q & 1) * ts / 2, (q >> 1) * ts / 2, ts / 2, ts / 2)));
      }
      writer.Submit(p, parent);
      result.written.insert(p);
    }
    writer.Flush();
    changed = std::move(parents);
  }
  store->Flush();
  return result;
}

}  // namespace seamap
