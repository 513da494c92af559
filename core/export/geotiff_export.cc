#include "core/export/geotiff_export.h"

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cstdlib>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "core/mission/mission_metadata.h"
#include "core/tiles/tile_codec.h"
#include "core/util/error.h"

namespace seamap {
namespace {

constexpr double kHalfWorld_m = 20037508.342789244;  // EPSG:3857 half circumference

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
                   int colour_channels)
      : store_(store), zoom_(zoom), x0_(x0), y0_(y0), tile_px_(tile_px), colour_channels_(colour_channels) {
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

 private:
  const TileStore& store_;
  int zoom_, x0_, y0_, tile_px_, colour_channels_;
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
  const auto* f = static_cast<const std::function<void(double)>*>(arg);
  if (*f) (*f)(fraction);
  return TRUE;
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
}

GeotiffSummary ExportGeotiff(const TileStore& from, const std::string& source, const std::string& path,
                             const GeotiffOptions& options, const std::function<void(double)>& on_progress) {
  options.Check();
  // The level's tile-aligned extent, from the tile ids alone (no tile data in RAM).
  std::map<int, std::array<int, 5>> levels;  // zoom -> x0, y0, x1, y1, count
  for (const TileId& t : from.TileIds()) {
    auto [it, fresh] = levels.try_emplace(t.z, std::array<int, 5>{t.x, t.y, t.x, t.y, 0});
    auto& l = it->second;
    l = {std::min(l[0], t.x), std::min(l[1], t.y), std::max(l[2], t.x), std::max(l[3], t.y), l[4] + 1};
  }
  if (levels.empty()) throw InputError(source, 0, "tiles", "the map has no tiles to export");
  const int zoom = options.zoom < 0 ? levels.rbegin()->first : options.zoom;
  if (!levels.count(zoom))
    throw InputError("--zoom", 0, "",
                     "the map " + source + " has no tiles at zoom " + std::to_string(zoom) + "; it has zooms " +
                         std::to_string(levels.begin()->first) + ".." + std::to_string(levels.rbegin()->first));
  const auto& l = levels.at(zoom);
  const int tiles_x = l[2] - l[0] + 1, tiles_y = l[3] - l[1] + 1;

  const MissionMetadata mission = ReadMissionMetadata(from);
  int tile_px = mission.tile_size_px.value_or(256);
  int colour_channels = mission.channels.value_or(0);
  if (colour_channels != 1 && colour_channels != 3) {  // not a SeaMap map: ask one tile
    for (const TileId& t : from.TileIds()) {
      if (t.z != zoom) continue;
      const cv::Mat tile = DecodeTile(*from.GetTile(t));
      colour_channels = tile.channels() == 2 ? 1 : 3;
      tile_px = tile.cols;
      break;
    }
  }
  if (tile_px <= 0 || static_cast<int64_t>(tiles_x) * tile_px > INT_MAX ||
      static_cast<int64_t>(tiles_y) * tile_px > INT_MAX)
    throw InputError(source, 0, "--zoom", "level " + std::to_string(zoom) + " is too large for one GeoTIFF");

  GDALAllRegister();
  GDALDriver* cog = GetGDALDriverManager()->GetDriverByName("COG");
  if (!cog) throw std::runtime_error("GDAL has no COG driver (GDAL >= 3.1 needed)");
  TileLevelDataset level(from, zoom, l[0], l[1], tiles_x, tiles_y, tile_px, colour_channels);
  const std::string threads = options.threads == 0 ? "ALL_CPUS" : std::to_string(options.threads);
  const std::string block = "BLOCKSIZE=" + std::to_string(std::min(tile_px, 4096));
  const std::string resampling = "RESAMPLING=" + options.resampling;
  const std::string num_threads = "NUM_THREADS=" + threads;
  const char* create_options[] = {"COMPRESS=DEFLATE",  block.c_str(),      resampling.c_str(),
                                  num_threads.c_str(), "BIGTIFF=IF_SAFER", nullptr};
  CPLErrorReset();
  std::function<void(double)> progress = on_progress;
  CPLPushErrorHandler(CPLQuietErrorHandler);  // the message goes into our InputError instead
  GDALDataset* out =
      cog->CreateCopy(path.c_str(), &level, FALSE, const_cast<char**>(create_options), ProgressThunk, &progress);
  CPLPopErrorHandler();
  if (!out) {
    const std::string why = CPLGetLastErrorMsg();
    VSIUnlink(path.c_str());
    throw InputError(path, 0, "output", "GDAL could not write the GeoTIFF: " + (why.empty() ? "unknown error" : why));
  }
  GDALClose(out);

  GeotiffSummary s;
  s.zoom = zoom;
  s.width_px = level.GetRasterXSize();
  s.height_px = level.GetRasterYSize();
  s.bands = level.GetRasterCount();
  s.tiles = l[4];
  double gt[6];
  level.GetGeoTransform(gt);
  s.west_m = gt[0];
  s.north_m = gt[3];
  s.east_m = gt[0] + gt[1] * s.width_px;
  s.south_m = gt[3] + gt[5] * s.height_px;
  return s;
}

}  // namespace seamap
