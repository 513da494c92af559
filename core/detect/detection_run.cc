#include "core/detect/detection_run.h"

#include <algorithm>
#include <cmath>

#include "core/detect/detection_record.h"
#include "core/detect/level_rule.h"
#include "core/detect/search_levels.h"
#include "core/tiles/tile_codec.h"
#include "core/util/error.h"

namespace seamap {

std::vector<int> ChooseZooms(const std::optional<std::vector<int>>& requested, const std::string& option, int min_zoom,
                             int base_zoom, double lat, int tile_size, const YoloModelInfo& model) {
  if (requested) {
    for (int z : *requested)
      if (z < min_zoom || z > base_zoom + 1)
        throw InputError(option, 0, "",
                         "zoom " + std::to_string(z) + " is not in the map, which has zooms " +
                             std::to_string(min_zoom) + ".." + std::to_string(base_zoom) + " (and " +
                             std::to_string(base_zoom + 1) + " from them scaled up)");
    std::vector<int> zooms = *requested;
    std::sort(zooms.rbegin(), zooms.rend());
    zooms.erase(std::unique(zooms.begin(), zooms.end()), zooms.end());
    return zooms;
  }
  std::vector<int> zooms = ScaleMatchedZooms(model.class_sizes_m, base_zoom, min_zoom, lat, tile_size);
  if (!zooms.empty()) return zooms;
  double largest = 0;
  for (double s : model.class_sizes_m) largest = std::max(largest, s);
  if (largest <= 0) largest = 4.0;
  return DefaultZooms(base_zoom, min_zoom, largest, lat, tile_size, model.input.width);
}

TileReader StoreReader(const TileStore& store, int stored_zoom) {
  const auto decoded = [&store](const TileId& id) -> std::optional<cv::Mat> {
    const auto bytes = store.GetTile(id);
    if (!bytes) return std::nullopt;
    return DecodeTile(*bytes);
  };
  return [decoded, stored_zoom](const TileId& id) -> std::optional<cv::Mat> {
    if (id.z != stored_zoom + 1) return decoded(id);
    const std::optional<cv::Mat> parent = decoded({id.z - 1, id.x / 2, id.y / 2});
    return OverzoomedTile(id, parent, parent ? parent->cols : 0);
  };
}

std::vector<WindowKey> MapWindows(const TileStore& store, const std::vector<int>& zooms, int tile_size,
                                  int stored_zoom) {
  const bool over = std::find(zooms.begin(), zooms.end(), stored_zoom + 1) != zooms.end();
  std::vector<TileId> tiles;
  for (const TileId& t : store.TileIds()) {
    if (std::find(zooms.begin(), zooms.end(), t.z) != zooms.end()) tiles.push_back(t);
    if (over && t.z == stored_zoom)
      for (const TileId& c : ChildTiles(t)) tiles.push_back(c);
  }
  return WindowsHoldingAny(tiles, WindowTiles(tile_size));
}

WindowSearcher::WindowSearcher(const DetectSettings& settings)
    : settings_(settings),
      detector_(settings.model, settings.tile_size, ScoreThresholds{settings.min_score, settings.class_min_scores}) {}

void DetectStats::Add(const DetectStats& other) {
  window_ms.insert(window_ms.end(), other.window_ms.begin(), other.window_ms.end());
  searched += other.searched;
  skipped += other.skipped;
  non_finite += other.non_finite;
  capped_boxes += other.capped_boxes;
  capped_windows += other.capped_windows;
}

void WindowSearcher::Search(const WindowKey& w, const TileReader& read) {
  WindowSearch s = detector_.Search(w, read);
  if (s.skipped) {
    ++stats_.skipped;
    results_.Replace(w, {});
    return;
  }
  ++stats_.searched;
  stats_.non_finite += s.dropped.non_finite;
  stats_.capped_boxes += s.dropped.capped;
  stats_.capped_windows += s.dropped.capped > 0;
  stats_.window_ms.push_back(s.ms);
  results_.Replace(w, std::move(s.found));
}

std::vector<RecognisedObject> WindowSearcher::Objects(const std::vector<FrameRecord>& frames) const {
  return MergeSearched(settings_, results_.All(), frames);
}

std::vector<RecognisedObject> MergeSearched(const DetectSettings& settings, std::vector<RawDetection> raw,
                                            const std::vector<FrameRecord>& frames) {
  const LocalFrame frame(settings.origin);
  if (!settings.keep_cut_views) {
    const std::vector<int> whole =
        WholeViewZooms(settings.model->class_sizes_m, settings.zooms, settings.origin.lat, settings.tile_size);
    StitchCutViews(whole, settings.model->class_sizes_m, settings.origin.lat, settings.tile_size, &raw);
    DropCutViews(whole, &raw);
  }
  MergeOptions merge;
  merge.representative_zoom =
      RepresentativeZooms(settings.model->class_sizes_m, settings.zooms, settings.origin.lat, settings.tile_size);
  std::vector<RecognisedObject> objects =
      MergeDetections(std::move(raw), settings.model->class_names, settings.tile_size, frame, merge);
  for (RecognisedObject& o : objects) o.model = settings.model->name;
  AttachFrames(objects, frames);
  return objects;
}

}  // namespace seamap
