#pragma once
// The levels the recogniser searches, chosen by ground resolution: where the
// model's classes have the sizes it was trained on, whatever the survey's
// altitude. The shipped model learnt at the two levels where its largest class
// (a 3 m pipe) nearly fills a 256 px tile and its smallest (a rock of at most
// 0.8 m) does (zooms 23 and 25 at 43 N). A survey flown higher has a coarser
// base zoom: counting levels down from it (DefaultZooms) searched zooms 24 and
// 22, scales the model never saw. The finer trained level may lie one zoom
// above the map's base: its windows are composed from the base tiles scaled
// up 2x (OverzoomedTile).
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/geo/web_mercator.h"

namespace seamap {

// The zoom whose tile side (tile_size px) in metres is nearest, by ratio, to `size_m`.
int ZoomFittingSize(double size_m, double lat_deg, int tile_size);

// Finest first: from the zoom fitting the smallest class size to the one
// fitting the largest, 2 zooms apart (as trained), ending at the latter.
// Levels above base_zoom + 1 (more than 2x up-scaling) or below min_zoom are
// left out; empty when none is left or no class size is known (> 0).
std::vector<int> ScaleMatchedZooms(const std::vector<double>& class_sizes_m, int base_zoom, int min_zoom,
                                   double lat_deg, int tile_size);

// A tile one zoom above the map's finest stored zoom: the quarter of its
// parent, scaled up 2x (bilinear, alpha too); nullopt without a parent.
// `parent` is the decoded parent tile (CV_8UC2 or CV_8UC4) or nullopt.
std::optional<cv::Mat> OverzoomedTile(const TileId& id, const std::optional<cv::Mat>& parent, int tile_size);

// The tiles one zoom above `parent` (its four children).
std::vector<TileId> ChildTiles(const TileId& parent);

}  // namespace seamap
