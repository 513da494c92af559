#include "core/export/pmtiles_directory.h"

#include <libdeflate.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>

namespace seamap {
namespace {

// (4^z - 1) / 3: the number of tiles in zooms 0..z-1.
uint64_t FirstIdOfZoom(int z) {
  return ((uint64_t{1} << (2 * z)) - 1) / 3;
}

// The Hilbert curve's quadrant rotation (as in the spec's reference readers).
void Rotate(uint64_t n, uint64_t* x, uint64_t* y, uint64_t rx, uint64_t ry) {
  if (ry == 0) {
    if (rx == 1) {
      *x = n - 1 - *x;
      *y = n - 1 - *y;
    }
    std::swap(*x, *y);
  }
}

void PutVarint(uint64_t v, std::vector<uint8_t>* out) {
  while (v >= 0x80) {
    out->push_back(static_cast<uint8_t>(v | 0x80));
    v >>= 7;
  }
  out->push_back(static_cast<uint8_t>(v));
}

uint64_t GetVarint(const std::vector<uint8_t>& in, size_t* pos) {
  uint64_t v = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    if (*pos >= in.size()) throw std::runtime_error("PMTiles directory: truncated varint");
    const uint8_t b = in[(*pos)++];
    v |= static_cast<uint64_t>(b & 0x7f) << shift;
    if (!(b & 0x80)) return v;
  }
  throw std::runtime_error("PMTiles directory: varint longer than 64 bits");
}

}  // namespace

uint64_t PmtilesTileId(const TileId& tile) {
  if (tile.z < 0 || tile.z > 31)
    throw std::invalid_argument("PMTiles: zoom " + std::to_string(tile.z) + " not in 0..31");
  const uint64_t n = uint64_t{1} << tile.z;
  if (tile.x < 0 || tile.y < 0 || static_cast<uint64_t>(tile.x) >= n || static_cast<uint64_t>(tile.y) >= n)
    throw std::invalid_argument("PMTiles: tile outside the grid of zoom " + std::to_string(tile.z));
  uint64_t x = tile.x, y = tile.y, d = 0;
  for (uint64_t s = n / 2; s > 0; s /= 2) {
    const uint64_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
    d += s * s * ((3 * rx) ^ ry);
    Rotate(s, &x, &y, rx, ry);
  }
  return FirstIdOfZoom(tile.z) + d;
}

TileId PmtilesTileFromId(uint64_t tile_id) {
  int z = 0;
  while (z < 31 && FirstIdOfZoom(z + 1) <= tile_id) ++z;
  const uint64_t n = uint64_t{1} << z;
  uint64_t t = tile_id - FirstIdOfZoom(z), x = 0, y = 0;
  for (uint64_t s = 1; s < n; s *= 2) {
    const uint64_t rx = 1 & (t / 2), ry = 1 & (t ^ rx);
    Rotate(s, &x, &y, rx, ry);
    x += s * rx;
    y += s * ry;
    t /= 4;
  }
  return {z, static_cast<int>(x), static_cast<int>(y)};
}

std::vector<uint8_t> EncodePmtilesDirectory(const std::vector<PmtilesEntry>& entries) {
  std::vector<uint8_t> out;
  out.reserve(entries.size() * 6 + 8);
  PutVarint(entries.size(), &out);
  uint64_t last_id = 0;
  for (const auto& e : entries) {
    PutVarint(e.tile_id - last_id, &out);
    last_id = e.tile_id;
  }
  for (const auto& e : entries) PutVarint(e.run_length, &out);
  for (const auto& e : entries) PutVarint(e.length, &out);
  for (size_t i = 0; i < entries.size(); ++i) {
    const bool follows = i > 0 && entries[i].offset == entries[i - 1].offset + entries[i - 1].length;
    PutVarint(follows ? 0 : entries[i].offset + 1, &out);
  }
  return out;
}

std::vector<PmtilesEntry> DecodePmtilesDirectory(const std::vector<uint8_t>& bytes) {
  size_t pos = 0;
  const uint64_t n = GetVarint(bytes, &pos);
  if (n > bytes.size()) throw std::runtime_error("PMTiles directory: more entries than bytes");
  std::vector<PmtilesEntry> entries(n);
  uint64_t last_id = 0;
  for (auto& e : entries) e.tile_id = last_id += GetVarint(bytes, &pos);
  for (auto& e : entries) e.run_length = static_cast<uint32_t>(GetVarint(bytes, &pos));
  for (auto& e : entries) e.length = static_cast<uint32_t>(GetVarint(bytes, &pos));
  for (size_t i = 0; i < n; ++i) {
    const uint64_t v = GetVarint(bytes, &pos);
    if (v == 0 && i == 0) throw std::runtime_error("PMTiles directory: first offset is relative");
    entries[i].offset = v == 0 ? entries[i - 1].offset + entries[i - 1].length : v - 1;
  }
  return entries;
}

std::vector<uint8_t> GzipBytes(const std::vector<uint8_t>& bytes) {
  std::unique_ptr<libdeflate_compressor, void (*)(libdeflate_compressor*)> c(libdeflate_alloc_compressor(9),
                                                                             libdeflate_free_compressor);
  if (!c) throw std::bad_alloc();
  std::vector<uint8_t> out(libdeflate_gzip_compress_bound(c.get(), bytes.size()));
  out.resize(libdeflate_gzip_compress(c.get(), bytes.data(), bytes.size(), out.data(), out.size()));
  return out;
}

std::vector<uint8_t> GunzipBytes(const std::vector<uint8_t>& gzip) {
  // ISIZE, the last 4 bytes, is the size mod 2^32: enough for directories.
  if (gzip.size() < 18) throw std::runtime_error("gzip: truncated");
  const size_t n = gzip[gzip.size() - 4] | gzip[gzip.size() - 3] << 8 | gzip[gzip.size() - 2] << 16 |
                   static_cast<size_t>(gzip[gzip.size() - 1]) << 24;
  std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> d(libdeflate_alloc_decompressor(),
                                                                                 libdeflate_free_decompressor);
  std::vector<uint8_t> out(n);
  size_t got = 0;
  if (libdeflate_gzip_decompress(d.get(), gzip.data(), gzip.size(), out.data(), out.size(), &got) != LIBDEFLATE_SUCCESS)
    throw std::runtime_error("gzip: bad data");
  out.resize(got);
  return out;
}

PmtilesDirectories BuildPmtilesDirectories(const std::vector<PmtilesEntry>& entries, size_t max_root_bytes,
                                           size_t first_leaf_entries) {
  if (entries.empty()) throw std::invalid_argument("PMTiles: an archive needs at least one tile");
  PmtilesDirectories dirs;
  dirs.root = GzipBytes(EncodePmtilesDirectory(entries));
  if (dirs.root.size() <= max_root_bytes) return dirs;
  for (double leaf_entries = std::max<size_t>(first_leaf_entries, 1);; leaf_entries *= 1.2) {
    const size_t per_leaf = static_cast<size_t>(leaf_entries);
    std::vector<PmtilesEntry> root;
    dirs.leaves.clear();
    for (size_t i = 0; i < entries.size(); i += per_leaf) {
      const std::vector<PmtilesEntry> leaf(entries.begin() + i,
                                           entries.begin() + std::min(entries.size(), i + per_leaf));
      const std::vector<uint8_t> bytes = GzipBytes(EncodePmtilesDirectory(leaf));
      root.push_back({leaf.front().tile_id, dirs.leaves.size(), static_cast<uint32_t>(bytes.size()), 0});
      dirs.leaves.insert(dirs.leaves.end(), bytes.begin(), bytes.end());
    }
    dirs.root = GzipBytes(EncodePmtilesDirectory(root));
    dirs.leaf_count = root.size();
    if (dirs.root.size() <= max_root_bytes) return dirs;
  }
}

}  // namespace seamap
