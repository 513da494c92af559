#pragma once
// Running the recogniser over a map: which zooms, which windows, the
// search of each window and the merge of everything found. Used by
// `seamap detect` on a finished map and by LiveDetector during a build.
#include <memory>
#include <optional>
#include <vector>

#include "core/detect/recognised_object.h"
#include "core/detect/tile_detector.h"
#include "core/tiles/tile_store.h"

namespace seamap {

constexpr int kMaxStoredZoom = 30;

struct DetectSettings {
  std::shared_ptr<const YoloModelInfo> model;
  std::vector<int> zooms;  // searched levels
  // The map's finest stored zoom: a searched level one above it is composed
  // from its tiles scaled up (search_levels.h).
  int stored_zoom = kMaxStoredZoom;
  float min_score = 0.4f;
  // A threshold per class (by class id; the model's seamap.class_min_scores
  // unless --min-score is given); empty = min_score for every class.
  std::vector<float> class_min_scores;
  int tile_size = 256;
  LatLon origin;  // of the mission's local frame (position_m)
  // Keep boxes cut by a window edge of classes seen whole at some searched
  // level (level_rule.h drops them by default).
  bool keep_cut_views = false;
};

// The zooms to search: `requested` (--zooms), each of which the map must
// have or be one above its base (InputError naming `option` and listing the
// map's zooms), else the
// levels where the model's classes have their trained sizes
// (ScaleMatchedZooms, possibly base_zoom + 1), else (class sizes unknown)
// DefaultZooms for 4 m.
std::vector<int> ChooseZooms(const std::optional<std::vector<int>>& requested, const std::string& option, int min_zoom,
                             int base_zoom, double lat, int tile_size, const YoloModelInfo& model);

// Decoded tiles straight from a store (thread-safe like the store); tiles one
// zoom above `stored_zoom` are cut from their parents and scaled up.
TileReader StoreReader(const TileStore& store, int stored_zoom = kMaxStoredZoom);

// Every window holding a stored tile of one of `zooms` (at stored_zoom + 1: a
// child of a stored tile), in a fixed order.
std::vector<WindowKey> MapWindows(const TileStore& store, const std::vector<int>& zooms, int tile_size,
                                  int stored_zoom = kMaxStoredZoom);

struct DetectStats {
  std::vector<double> window_ms;  // searched windows
  int searched = 0, skipped = 0;  // skipped: under 2 % painted
  int64_t non_finite = 0;         // inf/NaN boxes dropped (never stored)
  int64_t capped_boxes = 0;       // boxes over a window's cap (YoloDropped)
  int capped_windows = 0;         // windows that proposed more than the cap
  void Add(const DetectStats& other);
};

// One net searching windows one after another (not thread-safe).
class WindowSearcher {
 public:
  explicit WindowSearcher(const DetectSettings& settings);
  void Search(const WindowKey& w, const TileReader& read);
  // The merged objects, with the frames that saw them.
  std::vector<RecognisedObject> Objects(const std::vector<FrameRecord>& frames) const;
  // The latest boxes of every window searched (to merge several searchers' with MergeSearched).
  std::vector<RawDetection> Raw() const { return results_.All(); }
  const DetectStats& stats() const { return stats_; }
  bool Searched(const WindowKey& w) const { return results_.Has(w); }

 private:
  DetectSettings settings_;
  TileDetector detector_;
  WindowResults results_;
  DetectStats stats_;
};

// Merges boxes (of one or several searchers) into objects with the frames that saw them.
std::vector<RecognisedObject> MergeSearched(const DetectSettings& settings, std::vector<RawDetection> raw,
                                            const std::vector<FrameRecord>& frames);

}  // namespace seamap
