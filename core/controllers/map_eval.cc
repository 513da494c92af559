#include "core/controllers/map_eval.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include <opencv2/imgproc.hpp>

#include "core/geo/local_frame.h"
#include "core/geo/web_mercator.h"
#include "core/sim/ground_truth.h"
#include "core/tiles/tile_codec.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"
#include "core/util/statistics.h"

namespace seamap {

void MapEvalOptions::Check() const {
  if (map.empty()) throw InputError("", 0, "MAP", "names no map");
  if (survey_dir.empty()) throw InputError("", 0, "SURVEY_DIR", "names no survey folder");
  if (block_px < 16 || block_px > 256 || (block_px & (block_px - 1)) != 0)
    throw InputError("", 0, "--block", "must be a power of two from 16 to 256 pixels");
}

MapEvaluation EvaluateMap(const MapEvalOptions& o) {
  o.Check();
  const GroundTruth truth = GroundTruth::Load(o.survey_dir);
  const LocalFrame frame(truth.origin);
  std::unique_ptr<TileStore> store = OpenExistingMap(o.map, /*writable=*/false);
  const auto meta = store->Metadata();
  auto field = [&](const std::string& key) {
    auto it = meta.find(key);
    if (it == meta.end()) throw InputError(o.map, 0, key, "missing from the map's metadata");
    return it->second;
  };
  const std::string zoom_text = field("maxzoom"), bounds_text = field("bounds");
  int z = 0;
  double w = 0, s = 0, e = 0, n = 0;
  if (std::sscanf(zoom_text.c_str(), "%d", &z) != 1 || z < 0 || z > 30)
    throw InputError(o.map, 0, "maxzoom", "not a zoom: " + zoom_text);
  if (std::sscanf(bounds_text.c_str(), "%lf,%lf,%lf,%lf", &w, &s, &e, &n) != 4)
    throw InputError(o.map, 0, "bounds", "not west,south,east,north: " + bounds_text);

  MapEvaluation out;
  const int block = o.block_px;
  const int ts = 256;
  const GlobalPixel nw = LatLonToPixel({n, w}, z, ts), se = LatLonToPixel({s, e}, z, ts);
  std::vector<double> offsets;
  for (int ty = static_cast<int>(nw.y / ts); ty <= static_cast<int>(se.y / ts); ++ty)
    for (int tx = static_cast<int>(nw.x / ts); tx <= static_cast<int>(se.x / ts); ++tx) {
      const auto bytes = store->GetTile({z, tx, ty});
      if (!bytes) continue;
      const cv::Mat tile = DecodeTile(*bytes);
      if (tile.empty() || tile.channels() < 2) throw InputError(o.map, 0, "tile", "cannot decode a base-zoom tile");
      if (tile.cols != ts || tile.rows != ts)
        throw InputError(o.map, 0, "tile size", "map-eval reads maps of 256-pixel tiles");
      cv::Mat east(ts, ts, CV_32F), north(ts, ts, CV_32F);
      for (int y = 0; y < ts; ++y)
        for (int x = 0; x < ts; ++x) {
          const LocalXY p =
              frame.FromLatLon(PixelToLatLon({double(tx) * ts + x + 0.5, double(ty) * ts + y + 0.5}, z, ts));
          east.at<float>(y, x) = static_cast<float>(p.east);
          north.at<float>(y, x) = static_cast<float>(p.north);
        }
      if (out.pixel_m == 0)
        out.pixel_m =
            std::hypot(east.at<float>(0, 1) - east.at<float>(0, 0), north.at<float>(0, 1) - north.at<float>(0, 0));
      cv::Mat expected = RenderTruth(truth, east, north);
      if (expected.channels() > 1) cv::cvtColor(expected, expected, cv::COLOR_BGR2GRAY);
      if (expected.depth() != CV_8U) expected.convertTo(expected, CV_8U, 1.0 / 257);
      cv::Mat built, alpha;
      cv::Mat gray = tile;
      if (tile.channels() == 4) cv::cvtColor(tile, gray, cv::COLOR_BGRA2GRAY);
      cv::extractChannel(gray, built, 0);
      cv::extractChannel(tile, alpha, tile.channels() - 1);
      ++out.tiles;
      for (int by = 0; by + block <= ts; by += block)
        for (int bx = 0; bx + block <= ts; bx += block) {
          const cv::Rect r(bx, by, block, block);
          if (cv::countNonZero(alpha(r) == 255) < block * block) continue;  // edge of the survey
          ++out.painted_blocks;
          cv::Mat a, b, window;
          built(r).convertTo(a, CV_64F);
          expected(r).convertTo(b, CV_64F);
          cv::Scalar sa, sb, da, db;
          cv::meanStdDev(a, sa, da);
          cv::meanStdDev(b, sb, db);
          if (da[0] < 2 || db[0] < 2) continue;  // featureless block: no shift measurable
          cv::createHanningWindow(window, r.size(), CV_64F);
          const cv::Point2d shift = cv::phaseCorrelate(a, b, window);
          offsets.push_back(std::hypot(shift.x, shift.y));
        }
    }
  std::sort(offsets.begin(), offsets.end());
  out.measured_blocks = static_cast<int>(offsets.size());
  if (!offsets.empty()) {
    // Order statistics, as the accuracy tests have always read them.
    out.median_px = offsets[offsets.size() / 2];
    out.p90_px = offsets[offsets.size() * 9 / 10];
    out.max_px = offsets.back();
  }
  out.offsets_px = offsets;
  const double mm = out.pixel_m * 1000;
  const double coverage = out.painted_blocks ? static_cast<double>(out.measured_blocks) / out.painted_blocks : 0;
  out.figures = {{"map", o.map},
                 {"survey", o.survey_dir},
                 {"zoom", z},
                 {"pixel_mm", mm},
                 {"tiles", out.tiles},
                 {"block_px", block},
                 {"painted_blocks", out.painted_blocks},
                 {"measured_blocks", out.measured_blocks},
                 {"coverage", coverage},
                 {"median_px", out.median_px},
                 {"p90_px", out.p90_px},
                 {"max_px", out.max_px},
                 {"median_mm", out.median_px * mm},
                 {"p90_mm", out.p90_px * mm},
                 {"max_mm", out.max_px * mm}};
  char line[320];
  std::snprintf(line, sizeof line,
                "texture offset vs truth over %d blocks of %d px (%d tiles, %.0f %% of painted blocks measurable): "
                "median %.2f px (%.1f mm), p90 %.2f px (%.1f mm), max %.2f px (%.1f mm); base pixel %.2f mm",
                out.measured_blocks, block, out.tiles, coverage * 100, out.median_px, out.median_px * mm, out.p90_px,
                out.p90_px * mm, out.max_px, out.max_px * mm, mm);
  out.text = line;
  if (out.tiles == 0) throw InputError(o.map, 0, "tiles", "no base-zoom tile within the map's bounds");
  return out;
}

}  // namespace seamap
