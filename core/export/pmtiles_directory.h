#pragma once
// PMTiles v3 directories (https://github.com/protomaps/PMTiles spec/v3):
// Hilbert tile ids, entries, their varint/columnar encoding, and the split
// into a root directory (within the archive's first 16 KiB) and leaves.
#include <cstdint>
#include <vector>

#include "core/geo/web_mercator.h"

namespace seamap {

// A run of `run_length` consecutive tile ids sharing one blob at `offset`
// (from the start of the tile data section); run_length 0 = a leaf
// directory at `offset` from the start of the leaf section.
struct PmtilesEntry {
  uint64_t tile_id = 0;
  uint64_t offset = 0;
  uint32_t length = 0;
  uint32_t run_length = 0;
};

// The id of a tile: tiles of lower zooms first, then the position on the
// zoom's Hilbert curve. Throws std::invalid_argument outside z 0..31 or the grid.
uint64_t PmtilesTileId(const TileId& tile);
TileId PmtilesTileFromId(uint64_t tile_id);

// One directory's bytes before compression: the entry count, then tile id
// deltas, run lengths, lengths and offsets (0 = right after the previous
// entry's blob, offset + 1 otherwise), all as unsigned LEB128 varints.
std::vector<uint8_t> EncodePmtilesDirectory(const std::vector<PmtilesEntry>& entries);
// Inverse of EncodePmtilesDirectory; throws std::runtime_error on bad bytes.
std::vector<PmtilesEntry> DecodePmtilesDirectory(const std::vector<uint8_t>& bytes);

// gzip (RFC 1952) via libdeflate: the archive's internal compression.
std::vector<uint8_t> GzipBytes(const std::vector<uint8_t>& bytes);
std::vector<uint8_t> GunzipBytes(const std::vector<uint8_t>& gzip);  // throws std::runtime_error

struct PmtilesDirectories {
  std::vector<uint8_t> root;    // gzipped
  std::vector<uint8_t> leaves;  // gzipped leaf directories, back to back (may be empty)
  size_t leaf_count = 0;
};

// Lays out the tile entries (ascending tile ids): everything in the root when
// its gzipped bytes fit `max_root_bytes`, otherwise leaves of N entries with
// N grown by 1.2x from 4096 (or `first_leaf_entries`) until the root of leaf
// pointers fits. Throws std::invalid_argument if entries is empty.
PmtilesDirectories BuildPmtilesDirectories(const std::vector<PmtilesEntry>& entries, size_t max_root_bytes,
                                           size_t first_leaf_entries = 4096);

}  // namespace seamap
