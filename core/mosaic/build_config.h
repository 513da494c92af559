#pragma once
// Everything that shapes a build, from a JSON config file (see config/*.json
// and the README) with command-line overrides applied on top.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/nav/nav_table.h"
#include "core/tiles/tile_codec.h"

namespace seamap {

struct BuildConfig {
  std::string name = "seamap mission";
  std::string attribution = "SeaMap";
  int tile_size = 256;           // 256 or 512
  std::optional<int> base_zoom;  // default: from the ground sample distance
  std::optional<int> min_zoom;   // default: where the survey fits one tile
  TileEncoding encoding;
  double feather_power = 1.0;  // weight = (edge tent)^power; higher favours frame centres
  // Consecutive frames hand each map pixel over to the one that sees it most
  // centrally, feathered across a seam spanning this share (0..1] of the way
  // from their midpoint to the neighbour's centre (see FrameWarper).
  double seam_band = 0.5;
  bool blend_all_overlaps = false;  // no handover: every overlapping frame blends everywhere (slower)
  int linger_frames = 1;            // a tile is finished when this many frames in a row miss it
  // Offline builds know every pose up front: a tile that a frame among the
  // next this many will be over again stays in the buffer instead of being
  // written and read back (0: off; live builds never look ahead).
  int lookahead_frames = 300;
  // With look-ahead, a JPEG frame's side-edge tail (FrameWarper::Warp) waits
  // until its tile is finished and is painted only where no other frame has
  // painted by then; its rows are decoded only if it is painted.
  bool defer_edge_tails = true;
  // Base buffer (3/4) and overview cache (1/4); besides, up to a sixteenth
  // each for the weights of finished tiles and for frames whose tails wait.
  int memory_cap_mb = 512;
  int batch_frames = 25;       // overviews and a transaction are flushed this often,
  double batch_seconds = 1.0;  // but not more often than this (fast offline builds)
  // Also write the tiles still being painted at every batch, so a live view
  // shows the map right under the vehicle (replay turns this on).
  bool live_tiles = false;
  int threads = 0;                        // 0: one per core
  double max_footprint_ratio = 25;        // reject frames whose footprint is this much larger than at nadir
  int sixteen_bit_white = 65535;          // 16-bit frames are scaled to 8 bit by 255/white
  NavReadOptions nav;                     // column names, utm zone, origin
  std::optional<nlohmann::json> enhance;  // the enhancement chain (core/enhance), if any
  // "raw", "enhanced" (frames pass through `enhance`) or "both" (the
  // enhanced map as the mission's second layer, "enhanced").
  std::string layers = "raw";
  // The "server" object, kept as written for the commands that serve (cli/server_setup).
  std::optional<nlohmann::json> server;
};

// Reads a config file; unknown keys and wrong types are InputErrors naming
// the file and the key.
BuildConfig LoadBuildConfig(const std::string& path);
// Applies one JSON object of settings (the same keys as the file) onto config.
void ApplyBuildConfig(const nlohmann::json& settings, const std::string& source, BuildConfig* config);

}  // namespace seamap
