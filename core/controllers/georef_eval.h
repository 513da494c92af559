#pragma once
// How far georef's keyframes (and cloud) are from a simulated survey's truth
// (seamap simulate-buoy): what `seamap georef-eval` runs.
#include <string>

#include <nlohmann/json.hpp>

namespace seamap {

struct GeorefEvalOptions {
  std::string nav_path;     // georef's nav.csv
  std::string truth_dir;    // truth.csv, truth.json (and cloud_truth.ply)
  std::string report_path;  // georef's report.json: sub-maps' scale and rotation errors ("": none)
  std::string points;       // georef's cloud against cloud_truth.ply ("": none)
};

struct GeorefEvaluation {
  nlohmann::json figures;  // as --json writes them
  std::string text;        // one line
};

// InputError naming the file (and line or field) that cannot be read or
// does not match the truth.
GeorefEvaluation EvaluateGeoref(const GeorefEvalOptions& options);

}  // namespace seamap
