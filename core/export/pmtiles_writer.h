#pragma once
// Writes a PMTiles v3 archive (a single file of tiles any static web host or
// object store can serve by HTTP range requests) one tile at a time: the
// tile data goes to a temporary file beside the archive, so memory holds the
// directory entries (24 bytes a tile) and never the tiles.
#include <cstdint>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/export/pmtiles_directory.h"
#include "core/geo/web_mercator.h"

namespace seamap {

enum class PmtilesTileType : uint8_t { kUnknown = 0, kMvt = 1, kPng = 2, kJpeg = 3, kWebp = 4 };

// What the header and metadata say about the tiles.
struct PmtilesArchiveInfo {
  PmtilesTileType tile_type = PmtilesTileType::kPng;
  LatLonBounds bounds;  // degrees
  double center_lon_deg = 0, center_lat_deg = 0;
  int center_zoom = 0;
  std::string metadata_json = "{}";     // stored gzipped
  size_t max_root_bytes = 16384 - 127;  // the spec's limit: header + root within 16 KiB
};

struct PmtilesSummary {
  uint64_t addressed_tiles = 0;  // tiles a reader finds
  uint64_t tile_entries = 0;     // directory entries (runs of identical neighbours count once)
  uint64_t tile_contents = 0;    // distinct blobs stored
  uint64_t archive_bytes = 0;
  size_t leaf_directories = 0;
  int min_zoom = 0, max_zoom = 0;
};

class PmtilesWriter {
 public:
  // Creates `path` (replacing it) and its temporary tile file `path`.tiles.tmp.
  // Throws InputError(path, 0, "output", ...) when either cannot be written.
  explicit PmtilesWriter(const std::string& path);
  ~PmtilesWriter();  // removes the temporary file; an unfinished archive too
  PmtilesWriter(const PmtilesWriter&) = delete;
  PmtilesWriter& operator=(const PmtilesWriter&) = delete;

  // Tiles must come in strictly increasing PmtilesTileId order (clustered
  // archive); bytes must be non-empty. Identical tiles are stored once.
  void Add(const TileId& tile, const std::vector<uint8_t>& bytes);

  // Writes header, root directory, metadata, leaves and then the tile data.
  // Throws std::invalid_argument when no tile was added, InputError on I/O errors.
  PmtilesSummary Finish(const PmtilesArchiveInfo& info);

 private:
  struct Blob {
    uint64_t offset;
    uint32_t length;
  };
  bool SameBytes(const Blob& blob, const std::vector<uint8_t>& bytes);
  void Fail(const std::string& what) const;

  std::string path_, data_path_;
  std::FILE* out_ = nullptr;
  std::FILE* data_ = nullptr;
  uint64_t data_bytes_ = 0;
  bool finished_ = false;
  std::vector<PmtilesEntry> entries_;
  std::unordered_multimap<uint64_t, Blob> blobs_;  // by crc32 and length
  int min_zoom_ = 99, max_zoom_ = -1;
};

}  // namespace seamap
