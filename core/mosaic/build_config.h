#pragma once
// Everything that shapes a build, one option struct per concern, each with a
// Check() that names the offending key. The config file is one flat JSON
// object (see config/*.json and the README); command-line overrides are
// applied on top through the same keys. Its "server" object belongs to the
// server (server/server_options.h): it is kept as written.
#include <cstddef>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/nav/nav_table.h"
#include "core/tiles/tile_codec.h"

namespace seamap {

// What the map is: its name, tiles and zooms.
struct MapSettings {
  std::string name = "seamap mission";
  std::string attribution = "SeaMap";
  int tile_size = 256;           // 256 or 512
  std::optional<int> base_zoom;  // default: from the ground sample distance
  std::optional<int> min_zoom;   // default: where the survey fits one tile
  TileEncoding encoding;
  void Check(const std::string& source) const;
};

// How overlapping frames blend (core/mosaic/blend_rule.h).
struct BlendSettings {
  double feather_power = 1.0;  // weight = (edge tent)^power; higher favours frame centres
  // Consecutive frames hand each map pixel over to the one that sees it most
  // centrally, feathered across a seam spanning this share (0..1] of the way
  // from their midpoint to the neighbour's centre.
  double seam_band = 0.5;
  bool blend_all_overlaps = false;  // no handover: every overlapping frame blends everywhere (slower)
  // Over a height model: hand over to the frame whose ray at the point is
  // nearest the vertical (false: nearest the image centre, as a flat build).
  // Off by default: at +-8 deg pitch/roll it gains 0.05 px of median but
  // fattens the tail at the swath's outer edges (docs/TERRAIN.md, "Nadir seams' worst block").
  bool nadir_seams = false;
  void Check(const std::string& source) const;
};

// When tiles are finished and written (core/mosaic/tile_buffer.h).
struct BufferSettings {
  int linger_frames = 1;  // a tile is finished when this many frames in a row miss it
  // Offline builds know every pose up front: a tile that a frame among the
  // next this many will be over again stays in the buffer instead of being
  // written and read back (0: off; live builds never look ahead).
  int lookahead_frames = 300;
  int memory_cap_mb = 512;     // shared out by MemoryBudget
  int batch_frames = 25;       // overviews and a transaction are flushed this often,
  double batch_seconds = 1.0;  // but not more often than this (fast offline builds)
  // `seamap build` saves what it needs to resume (--resume) at the first
  // batch this long after the last checkpoint (0: no checkpoints, not resumable).
  double checkpoint_seconds = 10.0;
  // Also write the tiles still being painted at every batch, so a live view
  // shows the map right under the vehicle (replay turns this on).
  bool live_tiles = false;
  void Check(const std::string& source) const;
};

// Which frames are mapped, and how they are read.
struct FrameSettings {
  double max_footprint_ratio = 25;  // reject frames whose footprint is this much larger than at nadir
  int sixteen_bit_white = 65535;    // 16-bit frames are scaled to 8 bit by 255/white
  // Frames whose header claims more pixels are refused unread (image_header.h).
  int max_image_pixels = 100'000'000;
  void Check(const std::string& source) const;
};

// What the navigation is worth, and whether to refine it from the photos
// before painting (the config's "navigation" object; core/trajectory).
struct NavigationSettings {
  bool refine = false;
  double noise_m = 0.05;           // stated white position noise
  double drift_m_per_min = 1.0;    // stated drift rate of dead reckoning
  double heading_noise_deg = 1.0;  // stated heading noise
  void Check(const std::string& source) const;
};

// The seabed's shape the frames are projected onto (a true orthophoto,
// core/mosaic/surface_projection.h): the config's "terrain", true to
// estimate it from the photos (build --terrain), or a height model's file
// (build --terrain-file DEM.tif). Neither: the plane at each frame's altitude.
struct TerrainSettings {
  bool estimate = false;
  std::string file;
  // For the estimate (build --max-relief, --dem-cell, --dem-max-sigma); 0:
  // the estimator's own default (seabed_terrain.h).
  double max_relief_m = 0, cell_m = 0, max_sigma_m = 0;
  std::string points_file = "";  // build --terrain-points: seabed points from elsewhere (seamap stereo-points)
  // After --refine-nav's bundle adjustment: fit the bundle's seabed points
  // (--terrain-from-bundle) instead of matching the photos again. Opt-in:
  // the bundle keeps few tracks a frame and the model from them measured
  // worse (21.6 against 17.2 mm rms; docs/TERRAIN.md).
  bool from_bundle = false;
  bool enabled() const { return estimate || !file.empty(); }
};

struct BuildConfig {
  MapSettings map;
  BlendSettings blend;
  BufferSettings buffer;
  FrameSettings frames;
  int threads = 0;     // 0: one per core
  NavReadOptions nav;  // column names, utm zone, origin
  NavigationSettings navigation;
  TerrainSettings terrain;
  std::optional<nlohmann::json> enhance;  // the enhancement chain (core/enhance), if any
  // "raw", "enhanced" (frames pass through `enhance`) or "both" (the
  // enhanced map as the mission's second layer, "enhanced").
  std::string layers = "raw";
  // The "server" object, kept as written for the commands that serve (cli/server_setup).
  std::optional<nlohmann::json> server;
  // The "detect" object ({"zooms": [25, 23]}), read by build/replay --detect (cli/detect_setup).
  std::optional<nlohmann::json> detect;
  void Check(const std::string& source) const;
};

// The shares of memory_cap_mb; they add up to the cap.
struct MemoryBudget {
  size_t frames_bytes;            // 1/8: frames loaded and waiting to be warped
  size_t tile_buffer_bytes;       // 5/8: base tiles being painted
  size_t overview_bytes;          // 3/16: overview tiles kept in RAM
  size_t finished_weights_bytes;  // 1/16: weights of finished tiles, for painting them again
  static MemoryBudget Of(int memory_cap_mb);
};

// Reads a config file; unknown keys, wrong types and values out of range
// are InputErrors naming the file and the key.
BuildConfig LoadBuildConfig(const std::string& path);
// Applies one JSON object of settings (the same keys as the file) onto
// config, then checks it; `source` names where they came from.
void ApplyBuildConfig(const nlohmann::json& settings, const std::string& source, BuildConfig* config);

}  // namespace seamap
