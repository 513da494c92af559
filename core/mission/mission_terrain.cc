#include "core/mission/mission_terrain.h"

#include <libdeflate.h>

#include <cmath>
#include <cstring>
#include <memory>

#include <nlohmann/json.hpp>

#include "core/util/error.h"

namespace seamap {
namespace {

constexpr const char* kFormat = "seamap-terrain";
constexpr int kVersion = 1;
constexpr const char* kEncoding = "zlib-float32le";

static_assert(sizeof(float) == 4, "float32 cells");

bool LittleEndian() {
  const uint16_t one = 1;
  uint8_t first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

// The cells as float32 little-endian: heights then sigma (NaN where none).
std::vector<uint8_t> RawCells(const HeightGrid& g) {
  const size_t n = static_cast<size_t>(g.rows()) * g.cols();
  std::vector<float> values(2 * n);
  for (int r = 0; r < g.rows(); ++r)
    for (int c = 0; c < g.cols(); ++c) {
      const size_t i = static_cast<size_t>(r) * g.cols() + c;
      values[i] = g.height_m(r, c);
      values[n + i] = g.sigma_m.empty() ? NAN : g.sigma_m(r, c);
    }
  std::vector<uint8_t> bytes(values.size() * 4);
  std::memcpy(bytes.data(), values.data(), bytes.size());
  if (!LittleEndian())
    for (size_t i = 0; i < bytes.size(); i += 4)
      std::swap(bytes[i], bytes[i + 3]), std::swap(bytes[i + 1], bytes[i + 2]);
  return bytes;
}

}  // namespace

TerrainBlob EncodeMissionTerrain(const MissionTerrain& terrain) {
  const HeightGrid& g = terrain.grid;
  const auto fail = [](const std::string& field, const std::string& message) {
    throw InputError("terrain", 0, field, message);
  };
  if (g.empty()) fail("height_m", "the height model is empty");
  if (static_cast<long>(g.rows()) * g.cols() > kMaxTerrainCells)
    fail("height_m", std::to_string(g.rows()) + " x " + std::to_string(g.cols()) + " cells: more than the " +
                         std::to_string(kMaxTerrainCells) + " a mission keeps");
  if (!g.sigma_m.empty() && g.sigma_m.size() != g.height_m.size()) fail("sigma_m", "not the size of height_m");
  if (!(std::isfinite(g.cell_m) && g.cell_m > 0)) fail("cell_m", "must be a positive number of metres");
  if (!std::isfinite(g.east0_m) || !std::isfinite(g.north0_m)) fail("east0_m", "the grid's corner is not finite");
  if (!std::isfinite(terrain.origin.lat) || !std::isfinite(terrain.origin.lon)) fail("origin", "not finite");

  const std::vector<uint8_t> raw = RawCells(g);
  std::unique_ptr<libdeflate_compressor, void (*)(libdeflate_compressor*)> compressor(libdeflate_alloc_compressor(6),
                                                                                      libdeflate_free_compressor);
  if (!compressor) throw std::bad_alloc();
  TerrainBlob blob;
  blob.cells.resize(libdeflate_zlib_compress_bound(compressor.get(), raw.size()));
  const size_t size =
      libdeflate_zlib_compress(compressor.get(), raw.data(), raw.size(), blob.cells.data(), blob.cells.size());
  if (size == 0) throw std::runtime_error("terrain: cannot compress the height model");
  blob.cells.resize(size);

  nlohmann::json h;
  h["format"] = kFormat;
  h["version"] = kVersion;
  h["rows"] = g.rows();
  h["cols"] = g.cols();
  h["cell_m"] = g.cell_m;
  h["east0_m"] = g.east0_m;
  h["north0_m"] = g.north0_m;
  h["origin"] = {terrain.origin.lat, terrain.origin.lon};
  h["has_depth_datum"] = g.has_depth_datum;
  h["encoding"] = kEncoding;
  h["bands"] = {"height_m", "sigma_m"};
  h["cells_bytes"] = blob.cells.size();
  h["cells_crc32"] = libdeflate_crc32(0, blob.cells.data(), blob.cells.size());
  blob.header_json = h.dump(1) + "\n";
  return blob;
}

MissionTerrain DecodeMissionTerrain(const TerrainBlob& blob, const std::string& where) {
  const auto fail = [&where](const std::string& message) -> void {
    throw InputError(where, 0, "terrain", "the stored height model " + message);
  };
  nlohmann::json h;
  try {
    h = nlohmann::json::parse(blob.header_json);
  } catch (const nlohmann::json::exception& e) {
    fail(std::string("has an unreadable header: ") + e.what());
  }
  MissionTerrain out;
  HeightGrid& g = out.grid;
  int rows = 0, cols = 0;
  uint64_t cells_bytes = 0, crc = 0;
  try {
    if (!h.is_object() || h.value("format", "") != kFormat) fail("is not one SeaMap wrote (header format)");
    if (h.at("version").get<int>() != kVersion)
      fail("is version " + h.at("version").dump() + "; this SeaMap reads version " + std::to_string(kVersion));
    if (h.at("encoding").get<std::string>() != kEncoding)
      fail("has an unknown encoding '" + h.at("encoding").get<std::string>() + "'");
    rows = h.at("rows").get<int>();
    cols = h.at("cols").get<int>();
    g.cell_m = h.at("cell_m").get<double>();
    g.east0_m = h.at("east0_m").get<double>();
    g.north0_m = h.at("north0_m").get<double>();
    out.origin = {h.at("origin").at(0).get<double>(), h.at("origin").at(1).get<double>()};
    g.has_depth_datum = h.at("has_depth_datum").get<bool>();
    cells_bytes = h.at("cells_bytes").get<uint64_t>();
    crc = h.at("cells_crc32").get<uint64_t>();
  } catch (const nlohmann::json::exception& e) {
    fail(std::string("has a bad header: ") + e.what());
  }
  if (rows <= 0 || cols <= 0 || static_cast<long>(rows) * cols > kMaxTerrainCells)
    fail("has an impossible size " + std::to_string(rows) + " x " + std::to_string(cols));
  if (!(std::isfinite(g.cell_m) && g.cell_m > 0) || !std::isfinite(g.east0_m) || !std::isfinite(g.north0_m))
    fail("has a bad geometry (cell_m, east0_m, north0_m)");
  if (!(std::abs(out.origin.lat) <= 90 && std::abs(out.origin.lon) <= 180)) fail("has a bad origin");
  if (blob.cells.size() != cells_bytes)
    fail("is cut short or being rewritten: " + std::to_string(blob.cells.size()) + " bytes of cells, the header says " +
         std::to_string(cells_bytes));
  if (libdeflate_crc32(0, blob.cells.data(), blob.cells.size()) != crc) fail("is corrupt (CRC-32 of the cells)");

  const size_t n = static_cast<size_t>(rows) * cols;
  std::vector<uint8_t> raw(2 * n * 4);
  std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> decompressor(
      libdeflate_alloc_decompressor(), libdeflate_free_decompressor);
  if (!decompressor) throw std::bad_alloc();
  size_t got = 0;
  if (libdeflate_zlib_decompress(decompressor.get(), blob.cells.data(), blob.cells.size(), raw.data(), raw.size(),
                                 &got) != LIBDEFLATE_SUCCESS ||
      got != raw.size())
    fail("is corrupt (its cells do not decompress to " + std::to_string(rows) + " x " + std::to_string(cols) +
         " x 2 floats)");
  if (!LittleEndian())
    for (size_t i = 0; i < raw.size(); i += 4) std::swap(raw[i], raw[i + 3]), std::swap(raw[i + 1], raw[i + 2]);
  g.height_m.create(rows, cols);
  g.sigma_m.create(rows, cols);
  std::memcpy(g.height_m.ptr<float>(), raw.data(), n * 4);
  std::memcpy(g.sigma_m.ptr<float>(), raw.data() + n * 4, n * 4);
  return out;
}

void WriteMissionTerrain(TileStore* store, const MissionTerrain& terrain) {
  store->Records().PutTerrain(EncodeMissionTerrain(terrain));
}

std::optional<MissionTerrain> ReadMissionTerrain(const TileStore& store, const std::string& where) {
  std::optional<TerrainBlob> blob;
  try {
    blob = store.Records().Terrain();
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(where, 0, "terrain", std::string("cannot read the height model: ") + e.what());
  }
  if (!blob) return std::nullopt;
  return DecodeMissionTerrain(*blob, where);
}

}  // namespace seamap
