#pragma once
// How far a built map's texture is from where a simulated survey's truth
// says it belongs (seamap simulate's truth/texture): what `seamap map-eval`
// runs, and what the accuracy tests and benches measure.
//
// Every base-zoom tile is compared with the truth texture resampled into the
// same tile (texture(e, n) belongs at map position (e, n); with relief the
// truth texture is the true orthophoto): in blocks of block_px x block_px
// pixels, fully painted and textured enough to measure, the shift between the
// two by phase correlation.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace seamap {

struct MapEvalOptions {
  std::string map;         // MAP.mbtiles or a folder map
  std::string survey_dir;  // seamap simulate --out (truth/texture.png, texture.json)
  int block_px = 64;       // --block: 16..256, a divisor of the tile size
  // InputError naming the option.
  void Check() const;
};

struct MapEvaluation {
  std::vector<double> offsets_px;  // one per measured block, sorted
  int tiles = 0;                   // base-zoom tiles compared
  int painted_blocks = 0;          // blocks fully painted
  int measured_blocks = 0;         // of those, textured enough to measure (offsets_px.size())
  double pixel_m = 0;              // a base pixel's side at the survey, metres
  double median_px = 0, p90_px = 0, max_px = 0;
  nlohmann::json figures;  // as --json writes them
  std::string text;        // one line
};

// InputError naming the file (or option) that cannot be read or does not fit.
MapEvaluation EvaluateMap(const MapEvalOptions& options);

}  // namespace seamap
