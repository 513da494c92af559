#include "core/export/geotiff_export.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "core/mission/mission_metadata.h"
#include "core/tiles/tile_codec.h"
#include "core/util/error.h"

namespace seamap {
namespace {

constexpr double kHalfWorld_m = 20037508.342789244;  // EPSG:3857 half circumference

// The caller's progress callback, for GDAL: an exception from it (Ctrl-C) must
// not cross GDAL's C++ frames; it is kept, GDAL is told to stop (a FALSE
// progress answer, a failed block read), and it is rethrown after. Blocks
// ask it too (Poll), since GDAL reports progress only every few rows of
// blocks: on a wide raster that is seconds apart.
struct Progress {
  const std::function<void(double)>* callback = nullptr;
  std::exception_ptr error;
  double fraction = 0;
  std::mutex mutex;

  // Calls the callback at `at`; false once it has thrown.
  bool Report(double at) {
    std::lock_guard<std::mutex> lock(mutex);
    if (error) return false;
    fraction = at;
    if (!callback || !*callback) return true;
    try {
      (*callback)(at);
    } catch (...) {
      error = std::current_exception();
      return false;
    }
    return true;
  }
  bool Poll() {
    double at = 0;
    {
      std::lock_guard<std::mutex> lock(mutex);
      at = fraction;
    }
    return Report(at);
  }
};

class TileLevelDataset;

// A band whose blocks are tiles: reading one block decodes the tile once and
// fills the other bands' blocks of it into GDAL's cache.
class TileBand : public GDALRasterBand {
 public:
  TileBand(TileLevelDataset* ds, int band, int tile_px, GDALColorInterp interp);
  CPLErr IReadBlock(int block_x, int block_y, void* data) override;
  GDALColorInterp GetColorInterpretation() override { return interp_; }

 private:
  GDALColorInterp interp_;
};

class TileLevelDataset : public GDALDataset {
 public:
  TileLevelDataset(const TileStore& store, int zoom, int x0, int y0, int tiles_x, int tiles_y, int tile_px,
                   int colour_channels, Progress* progress)
      : store_(store),
        zoom_(zoom),
        x0_(x0),
        y0_(y0),
        tile_px_(tile_px),
        colour_channels_(colour_channels),
        progress_(progress) {
    nRasterXSize = tiles_x * tile_px;
    nRasterYSize = tiles_y * tile_px;
    const std::vector<GDALColorInterp> interps =
        colour_channels == 1 ? std::vector<GDALColorInterp>{GCI_GrayIndex, GCI_AlphaBand}
                             : std::vector<GDALColorInterp>{GCI_RedBand, GCI_GreenBand, GCI_BlueBand, GCI_AlphaBand};
    for (size_t b = 0; b < interps.size(); ++b)
      SetBand(static_cast<int>(b + 1), new TileBand(this, static_cast<int>(b + 1), tile_px, interps[b]));
    OGRSpatialReference srs;
    srs.importFromEPSG(3857);
    srs_ = srs.Clone();
  }
  ~TileLevelDataset() override {
    if (srs_) srs_->Release();
  }

  CPLErr GetGeoTransform(double* gt) override {
    const double tile_m = 2 * kHalfWorld_m / static_cast<double>(1LL << zoom_);
    gt[0] = -kHalfWorld_m + x0_ * tile_m;
    gt[1] = tile_m / tile_px_;
    gt[2] = 0;
    gt[3] = kHalfWorld_m - y0_ * tile_m;
    gt[4] = 0;
    gt[5] = -tile_m / tile_px_;
    return CE_None;
  }
  const OGRSpatialReference* GetSpatialRef() const override { return srs_; }

  // The tile at block (bx, by), band-ordered as the output: gray+alpha or
  // RGBA; empty when the map has no tile there (GDAL then writes zeros:
  // transparent).
  cv::Mat Tile(int bx, int by) {
    auto bytes = store_.GetTile({zoom_, x0_ + bx, y0_ + by});
    if (!bytes) return {};
    cv::Mat tile = WithColourChannels(DecodeTile(*bytes), colour_channels_);
    if (tile.cols != tile_px_ || tile.rows != tile_px_)
      throw std::runtime_error("tile " + std::to_string(zoom_) + "/" + std::to_string(x0_ + bx) + "/" +
                               std::to_string(y0_ + by) + " is " + std::to_string(tile.cols) + "x" +
                               std::to_string(tile.rows) + " px, not " + std::to_string(tile_px_));
    if (tile.channels() == 4) cv::cvtColor(tile, tile, cv::COLOR_BGRA2RGBA);
    return tile;
  }

  // Every 16th block read asks the caller whether to go on (Ctrl-C).
  bool GoOn() { return ++blocks_read_ % 16 != 0 || progress_->Poll(); }

 private:
  const TileStore& store_;
  int zoom_, x0_, y0_, tile_px_, colour_channels_;
  Progress* progress_;
  std::atomic<int64_t> blocks_read_{0};
  OGRSpatialReference* srs_ = nullptr;
};

TileBand::TileBand(TileLevelDataset* ds, int band, int tile_px, GDALColorInterp interp) : interp_(interp) {
  poDS = ds;
  nBand = band;
  eDataType = GDT_Byte;
  nBlockXSize = tile_px;
  nBlockYSize = tile_px;
}

CPLErr TileBand::IReadBlock(int block_x, int block_y, void* data) {
  auto* ds = static_cast<TileLevelDataset*>(poDS);
  if (!ds->GoOn()) return CE_Failure;
  cv::Mat tile;
  try {
    tile = ds->Tile(block_x, block_y);
  } catch (const std::exception& e) {
    CPLError(CE_Failure, CPLE_AppDefined, "%s", e.what());
    return CE_Failure;
  }
  const int bands = ds->GetRasterCount();
  for (int b = 1; b <= bands; ++b) {
    GByte* dst = static_cast<GByte*>(data);
    GDALRasterBlock* block = nullptr;
    if (b != nBand) {  // fill the sibling band's block unless it is cached already
      GDALRasterBand* other = ds->GetRasterBand(b);
      if ((block = other->TryGetLockedBlockRef(block_x, block_y)) != nullptr) {
        block->DropLock();
        continue;
      }
      if ((block = other->GetLockedBlockRef(block_x, block_y, TRUE)) == nullptr) continue;
      dst = static_cast<GByte*>(block->GetDataRef());
    }
    const size_t n = static_cast<size_t>(nBlockXSize) * nBlockYSize;
    if (tile.empty()) {
      std::fill(dst, dst + n, GByte{0});
    } else {
      const uint8_t* src = tile.ptr<uint8_t>();
      for (size_t i = 0; i < n; ++i) dst[i] = src[i * bands + (b - 1)];
    }
    if (block) block->DropLock();
  }
  return CE_None;
}

int ProgressThunk(double fraction, const char*, void* arg) {
  return static_cast<Progress*>(arg)->Report(fraction) ? TRUE : FALSE;
}

// What a failed or stopped export leaves: the partial file and the COG
// driver's temporary overviews (`path`.ovr.tmp, `path`.msk.ovr.tmp).
void RemovePartialGeotiff(const std::string& path) {
  for (const std::string& file : {path, path + ".ovr.tmp", path + ".msk.ovr.tmp"}) VSIUnlink(file.c_str());
}

// A level's tiles that hold data: their extent (inclusive) and count.
struct LevelExtent {
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  int64_t tiles = 0;
  void Add(int x, int y) {
    if (tiles++ == 0) {
      x0 = x1 = x;
      y0 = y1 = y;
      return;
    }
    x0 = std::min(x0, x);
    y0 = std::min(y0, y);
    x1 = std::max(x1, x);
    y1 = std::max(y1, y);
  }
  int64_t Width() const { return int64_t{x1} - x0 + 1; }
  int64_t Height() const { return int64_t{y1} - y0 + 1; }
  double Pixels(int tile_px) const { return static_cast<double>(Width()) * Height() * tile_px * tile_px; }
  double FilledShare() const { return static_cast<double>(tiles) / (static_cast<double>(Width()) * Height()); }
  bool Sparse(int tile_px) const {
    return Pixels(tile_px) > kSparseRasterPixels && FilledShare() < kSparseMaxFilledShare;
  }
};

// The tiles of `zoom` (inclusive x0, y0, x1, y1) that touch `b`.
std::array<int, 4> TileRange(const LatLonBounds& b, int zoom) {
  const GlobalPixel nw = LatLonToPixel({b.north, b.west}, zoom, 1);
  const GlobalPixel se = LatLonToPixel({b.south, b.east}, zoom, 1);
  const double last = std::ldexp(1.0, zoom) - 1;
  auto cell = [&](double v) { return static_cast<int>(std::clamp(std::floor(v), 0.0, last)); };
  return {cell(nw.x), cell(nw.y), cell(se.x), cell(se.y)};
}

// Where most of a level's tiles are: split the tiles where consecutive
// columns, then rows, are more than kGapTiles apart and keep the part with
// the most tiles (a frame placed kilometres off is left out).
constexpr int kGapTiles = 16;

LevelExtent MainPart(std::vector<std::pair<int, int>> tiles) {
  auto keep_largest = [&](bool by_x) {
    auto key = [by_x](const std::pair<int, int>& t) { return by_x ? t.first : t.second; };
    std::sort(tiles.begin(), tiles.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
    size_t best_begin = 0, best_end = 0;
    for (size_t begin = 0, i = 1; i <= tiles.size(); ++i) {
      if (i < tiles.size() && int64_t{key(tiles[i])} - key(tiles[i - 1]) <= kGapTiles) continue;
      if (i - begin > best_end - best_begin) best_begin = begin, best_end = i;
      begin = i;
    }
    tiles = std::vector<std::pair<int, int>>(tiles.begin() + best_begin, tiles.begin() + best_end);
  };
  keep_largest(true);
  keep_largest(false);
  LevelExtent main;
  for (const auto& [x, y] : tiles) main.Add(x, y);
  return main;
}

std::string Degrees(const LatLonBounds& b) {
  char text[128];
  std::snprintf(text, sizeof text, "%.7f,%.7f,%.7f,%.7f", b.west, b.south, b.east, b.north);
  return text;
}

LatLonBounds BoundsOf(const LevelExtent& e, int zoom) {
  const LatLonBounds nw = TileBounds({zoom, e.x0, e.y0}), se = TileBounds({zoom, e.x1, e.y1});
  return {nw.west, se.south, se.east, nw.north};
}

// The refusal of a huge, mostly empty raster: how big, how empty, and the ways out.
std::string SparseMessage(const std::string& source, int zoom, const LevelExtent& level, int tile_px, int bands,
                          const std::vector<std::pair<int, int>>& tiles, const std::map<int, LevelExtent>& levels) {
  char text[512];
  std::snprintf(text, sizeof text,
                "zoom %d of %s would be a GeoTIFF of %lld x %lld px (%.1f gigapixels, %.1f GB before compression) "
                "of which %s%.2f %% is empty: %lld of %lld tiles hold data. ",
                zoom, source.c_str(), static_cast<long long>(level.Width() * tile_px),
                static_cast<long long>(level.Height() * tile_px), level.Pixels(tile_px) / 1e9,
                level.Pixels(tile_px) * bands / 1e9, level.FilledShare() < 1e-4 ? "over " : "",
                level.FilledShare() < 1e-4 ? 99.99 : 100.0 * (1.0 - level.FilledShare()),
                static_cast<long long>(level.tiles), static_cast<long long>(level.Width() * level.Height()));
  std::string out = text;
  const LevelExtent main = MainPart(tiles);
  out += "Choose the area with --bounds W,S,E,N";
  if (main.tiles < level.tiles) {
    std::snprintf(text, sizeof text, " (%lld of the %lld tiles, %lld x %lld px, lie within %s)",
                  static_cast<long long>(main.tiles), static_cast<long long>(level.tiles),
                  static_cast<long long>(main.Width() * tile_px), static_cast<long long>(main.Height() * tile_px),
                  Degrees(BoundsOf(main, zoom)).c_str());
    out += text;
  }
  for (auto it = levels.rbegin(); it != levels.rend(); ++it) {
    if (it->first >= zoom || it->second.Sparse(tile_px)) continue;
    std::snprintf(text, sizeof text, ", or a coarser --zoom (zoom %d: %lld x %lld px)", it->first,
                  static_cast<long long>(it->second.Width() * tile_px),
                  static_cast<long long>(it->second.Height() * tile_px));
    out += text;
    break;
  }
  return out + ", or pass --allow-sparse to write it anyway";
}

}  // namespace

void GeotiffOptions::Check() const {
  if (zoom < -1 || zoom > 30) throw InputError("--zoom", 0, "", "must be 0..30, got " + std::to_string(zoom));
  static const std::set<std::string> kResampling = {"NEAREST",     "AVERAGE", "BILINEAR", "CUBIC",
                                                    "CUBICSPLINE", "LANCZOS", "MODE",     "RMS"};
  if (!kResampling.count(resampling))
    throw InputError("--resampling", 0, "",
                     "'" + resampling + "' is not one of NEAREST, AVERAGE, BILINEAR, CUBIC, LANCZOS, MODE, RMS");
  if (threads < 0) throw InputError("--threads", 0, "", "must be >= 0");
  if (bounds) {
    const LatLonBounds& b = *bounds;
    if (!(b.west >= -180 && b.east <= 180 && b.west < b.east))
      throw InputError("--bounds", 0, "", "west and east must be degrees in -180..180 with west < east");
    if (!(b.south >= -kWebMercatorMaxLat && b.north <= kWebMercatorMaxLat && b.south < b.north))
      throw InputError("--bounds", 0, "", "south and north must be degrees in -85.05..85.05 with south < north");
  }
}

LatLonBounds ParseGeotiffBounds(const std::string& text) {
  const std::string quoted = "'" + (text.size() > 100 ? text.substr(0, 100) + "..." : text) + "'";
  std::vector<double> v;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, ',');) {
    size_t used = 0;
    double value = NAN;
    try {
      value = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || part.find_first_not_of(" ", used) != std::string::npos || !std::isfinite(value))
      throw InputError("--bounds", 0, "", "expected W,S,E,N in degrees (four numbers), got " + quoted);
    v.push_back(value);
  }
  if (v.size() != 4 || (!text.empty() && text.back() == ','))
    throw InputError("--bounds", 0, "", "expected W,S,E,N in degrees (four numbers), got " + quoted);
  return {v[0], v[1], v[2], v[3]};
}

GeotiffSummary ExportGeotiff(const TileStore& from, const std::string& source, const std::string& path,
                             const GeotiffOptions& options, const std::function<void(double)>& on_progress) {
  options.Check();
  // Each level's tile-aligned extent (within --bounds), from the tile ids alone (no tile data in RAM).
  const std::vector<TileId> ids = from.TileIds();
  std::map<int, LevelExtent> levels;
  std::map<int, std::array<int, 4>> ranges;  // --bounds at each zoom
  for (const TileId& t : ids) {
    if (options.bounds) {
      auto [it, fresh] = ranges.try_emplace(t.z);
      if (fresh) it->second = TileRange(*options.bounds, t.z);
      const auto& r = it->second;
      if (t.x < r[0] || t.x > r[2] || t.y < r[1] || t.y > r[3]) continue;
    }
    levels[t.z].Add(t.x, t.y);
  }
  if (ids.empty()) throw InputError(source, 0, "tiles", "the map has no tiles to export");
  if (levels.empty())
    throw InputError("--bounds", 0, "", "no tile of " + source + " lies within " + Degrees(*options.bounds));
  const int zoom = options.zoom < 0 ? levels.rbegin()->first : options.zoom;
  if (!levels.count(zoom)) {
    if (options.bounds && std::any_of(ids.begin(), ids.end(), [&](const TileId& t) { return t.z == zoom; }))
      throw InputError(
          "--bounds", 0, "",
          "no tile of zoom " + std::to_string(zoom) + " of " + source + " lies within " + Degrees(*options.bounds));
    throw InputError("--zoom", 0, "",
                     "the map " + source + " has no tiles at zoom " + std::to_string(zoom) + "; it has zooms " +
                         std::to_string(levels.begin()->first) + ".." + std::to_string(levels.rbegin()->first));
  }
  const LevelExtent& extent = levels.at(zoom);
  const int64_t tiles_x = extent.Width(), tiles_y = extent.Height();

  const MissionMetadata mission = ReadMissionMetadata(from);
  int tile_px = mission.tile_size_px.value_or(256);
  int colour_channels = mission.channels.value_or(0);
  if (colour_channels != 1 && colour_channels != 3) {  // not a SeaMap map: ask one tile
    for (const TileId& t : ids) {
      if (t.z != zoom) continue;
      const cv::Mat tile = DecodeTile(*from.GetTile(t));
      colour_channels = tile.channels() == 2 ? 1 : 3;
      tile_px = tile.cols;
      break;
    }
  }
  if (tile_px <= 0) throw InputError(source, 0, "seamap_tile_size", "tiles must be at least 1 px");
  const int bands = colour_channels == 1 ? 2 : 4;
  if (extent.Sparse(tile_px) && !options.allow_sparse) {
    std::vector<std::pair<int, int>> tiles;  // the level's tiles, for the main part's bounds
    tiles.reserve(static_cast<size_t>(extent.tiles));
    for (const TileId& t : ids)
      if (t.z == zoom && t.x >= extent.x0 && t.x <= extent.x1 && t.y >= extent.y0 && t.y <= extent.y1)
        tiles.emplace_back(t.x, t.y);
    throw InputError("--zoom/--bounds", 0, "", SparseMessage(source, zoom, extent, tile_px, bands, tiles, levels));
  }
  if (tiles_x * tile_px > INT_MAX || tiles_y * tile_px > INT_MAX)
    throw InputError(source, 0, "--zoom", "level " + std::to_string(zoom) + " is too large for one GeoTIFF");

  GDALAllRegister();
  // GDAL's block cache defaults to 5 % of RAM (6 GB on a 128 GB machine); the
  // export reads each tile once, so 256 MiB is plenty and bounds its memory.
  if (!CPLGetConfigOption("GDAL_CACHEMAX", nullptr)) GDALSetCacheMax64(int64_t{256} << 20);
  GDALDriver* cog = GetGDALDriverManager()->GetDriverByName("COG");
  if (!cog) throw std::runtime_error("GDAL has no COG driver (GDAL >= 3.1 needed)");
  Progress progress;
  progress.callback = &on_progress;
  TileLevelDataset level(from, zoom, extent.x0, extent.y0, static_cast<int>(tiles_x), static_cast<int>(tiles_y),
                         tile_px, colour_channels, &progress);
  const std::string threads = options.threads == 0 ? "ALL_CPUS" : std::to_string(options.threads);
  const std::string block = "BLOCKSIZE=" + std::to_string(std::min(tile_px, 4096));
  const std::string resampling = "RESAMPLING=" + options.resampling;
  const std::string num_threads = "NUM_THREADS=" + threads;
  const char* create_options[] = {"COMPRESS=DEFLATE",  block.c_str(),      resampling.c_str(),
                                  num_threads.c_str(), "BIGTIFF=IF_SAFER", nullptr};
  CPLErrorReset();
  CPLPushErrorHandler(CPLQuietErrorHandler);  // the message goes into our InputError instead
  GDALDataset* out =
      cog->CreateCopy(path.c_str(), &level, FALSE, const_cast<char**>(create_options), ProgressThunk, &progress);
  CPLPopErrorHandler();
  if (!out || progress.error) {
    const std::string why = CPLGetLastErrorMsg();
    if (out) GDALClose(out);
    RemovePartialGeotiff(path);
    if (progress.error) std::rethrow_exception(progress.error);
    throw InputError(path, 0, "output", "GDAL could not write the GeoTIFF: " + (why.empty() ? "unknown error" : why));
  }
  GDALClose(out);

  GeotiffSummary s;
  s.zoom = zoom;
  s.width_px = level.GetRasterXSize();
  s.height_px = level.GetRasterYSize();
  s.bands = level.GetRasterCount();
  s.tiles = static_cast<int>(extent.tiles);
  double gt[6];
  level.GetGeoTransform(gt);
  s.west_m = gt[0];
  s.north_m = gt[3];
  s.east_m = gt[0] + gt[1] * s.width_px;
  s.south_m = gt[3] + gt[5] * s.height_px;
  return s;
}

}  // namespace seamap
