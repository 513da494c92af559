#include "core/export/pmtiles_writer.h"

#include <libdeflate.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <stdexcept>

#include "core/util/error.h"

namespace seamap {
namespace {

void PutLe(uint64_t v, int bytes, std::vector<uint8_t>* out) {
  for (int i = 0; i < bytes; ++i) out->push_back(static_cast<uint8_t>(v >> (8 * i)));
}

// Degrees as the header's signed 32-bit integers of 1e-7 degrees.
void PutE7(double deg, std::vector<uint8_t>* out) {
  PutLe(static_cast<uint32_t>(static_cast<int32_t>(std::lround(deg * 1e7))), 4, out);
}

}  // namespace

PmtilesWriter::PmtilesWriter(const std::string& path) : path_(path), data_path_(path + ".tiles.tmp") {
  out_ = std::fopen(path_.c_str(), "wb");
  if (!out_) Fail("cannot be created");
  data_ = std::fopen(data_path_.c_str(), "w+b");
  if (!data_) Fail("cannot create its temporary tile file " + data_path_);
  std::setvbuf(data_, nullptr, _IOFBF, 1 << 20);
}

PmtilesWriter::~PmtilesWriter() {
  if (data_) std::fclose(data_);
  if (out_) std::fclose(out_);
  std::error_code ec;
  std::filesystem::remove(data_path_, ec);
  if (!finished_) std::filesystem::remove(path_, ec);
}

void PmtilesWriter::Fail(const std::string& what) const {
  throw InputError(path_, 0, "output", what + (errno ? std::string(": ") + std::strerror(errno) : ""));
}

bool PmtilesWriter::SameBytes(const Blob& blob, const std::vector<uint8_t>& bytes) {
  if (blob.length != bytes.size()) return false;
  if (std::fflush(data_) != 0) Fail("cannot write its temporary tile file");
  std::vector<uint8_t> stored(blob.length);
  if (pread(fileno(data_), stored.data(), stored.size(), static_cast<off_t>(blob.offset)) !=
      static_cast<ssize_t>(stored.size()))
    Fail("cannot read back its temporary tile file");
  return stored == bytes;
}

void PmtilesWriter::Add(const TileId& tile, const std::vector<uint8_t>& bytes) {
  if (bytes.empty()) throw std::invalid_argument("PMTiles: empty tile");
  const uint64_t id = PmtilesTileId(tile);
  if (!entries_.empty() && id < entries_.back().tile_id + entries_.back().run_length)
    throw std::invalid_argument("PMTiles: tiles must be added in increasing tile id order");
  min_zoom_ = std::min(min_zoom_, tile.z);
  max_zoom_ = std::max(max_zoom_, tile.z);

  const uint64_t key = (uint64_t{libdeflate_crc32(0, bytes.data(), bytes.size())} << 32) ^ bytes.size();
  const Blob* found = nullptr;
  auto range = blobs_.equal_range(key);
  for (auto it = range.first; it != range.second && !found; ++it)
    if (SameBytes(it->second, bytes)) found = &it->second;
  Blob blob{data_bytes_, static_cast<uint32_t>(bytes.size())};
  if (found) {
    blob = *found;
  } else {
    if (std::fwrite(bytes.data(), 1, bytes.size(), data_) != bytes.size()) Fail("cannot write its tile data");
    data_bytes_ += bytes.size();
    blobs_.emplace(key, blob);
  }
  if (!entries_.empty()) {
    PmtilesEntry& last = entries_.back();
    if (last.tile_id + last.run_length == id && last.offset == blob.offset && last.length == blob.length &&
        last.run_length < UINT32_MAX) {
      ++last.run_length;  // a run of identical neighbours: one entry
      return;
    }
  }
  entries_.push_back({id, blob.offset, blob.length, 1});
}

PmtilesSummary PmtilesWriter::Finish(const PmtilesArchiveInfo& info) {
  if (entries_.empty()) throw std::invalid_argument("PMTiles: an archive needs at least one tile");
  const PmtilesDirectories dirs = BuildPmtilesDirectories(entries_, info.max_root_bytes);
  const std::vector<uint8_t> metadata =
      GzipBytes(std::vector<uint8_t>(info.metadata_json.begin(), info.metadata_json.end()));

  PmtilesSummary s;
  for (const auto& e : entries_) s.addressed_tiles += e.run_length;
  s.tile_entries = entries_.size();
  s.tile_contents = blobs_.size();
  s.leaf_directories = dirs.leaf_count;
  s.min_zoom = min_zoom_;
  s.max_zoom = max_zoom_;

  const uint64_t root_offset = 127, metadata_offset = root_offset + dirs.root.size();
  const uint64_t leaves_offset = metadata_offset + metadata.size();
  const uint64_t data_offset = leaves_offset + dirs.leaves.size();
  std::vector<uint8_t> h = {'P', 'M', 'T', 'i', 'l', 'e', 's', 3};
  for (uint64_t v :
       {root_offset, uint64_t{dirs.root.size()}, metadata_offset, uint64_t{metadata.size()}, leaves_offset,
        uint64_t{dirs.leaves.size()}, data_offset, data_bytes_, s.addressed_tiles, s.tile_entries, s.tile_contents})
    PutLe(v, 8, &h);
  h.push_back(1);  // clustered: blobs in tile id order
  h.push_back(2);  // internal compression: gzip
  h.push_back(1);  // tile compression: none (PNG/JPEG/WebP are compressed already)
  h.push_back(static_cast<uint8_t>(info.tile_type));
  h.push_back(static_cast<uint8_t>(min_zoom_));
  h.push_back(static_cast<uint8_t>(max_zoom_));
  PutE7(info.bounds.west, &h);
  PutE7(info.bounds.south, &h);
  PutE7(info.bounds.east, &h);
  PutE7(info.bounds.north, &h);
  h.push_back(static_cast<uint8_t>(info.center_zoom));
  PutE7(info.center_lon_deg, &h);
  PutE7(info.center_lat_deg, &h);

  errno = 0;
  for (const std::vector<uint8_t>* part :
       std::initializer_list<const std::vector<uint8_t>*>{&h, &dirs.root, &metadata, &dirs.leaves})
    if (std::fwrite(part->data(), 1, part->size(), out_) != part->size()) Fail("cannot be written");
  if (std::fflush(data_) != 0 || std::fseek(data_, 0, SEEK_SET) != 0) Fail("cannot read back its tile data");
  std::vector<char> buffer(4 << 20);
  for (size_t n; (n = std::fread(buffer.data(), 1, buffer.size(), data_)) > 0;)
    if (std::fwrite(buffer.data(), 1, n, out_) != n) Fail("cannot be written");
  if (std::ferror(data_)) Fail("cannot read back its tile data");
  const int closed = std::fclose(out_);
  out_ = nullptr;
  if (closed != 0) Fail("cannot be written");
  s.archive_bytes = data_offset + data_bytes_;
  finished_ = true;
  std::fclose(data_);
  data_ = nullptr;
  std::error_code ec;
  std::filesystem::remove(data_path_, ec);
  return s;
}

}  // namespace seamap
