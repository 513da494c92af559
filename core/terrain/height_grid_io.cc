#include "core/terrain/height_grid_io.h"

#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <sstream>
#include <vector>

#include "core/geo/utm.h"
#include "core/util/error.h"

namespace seamap {
namespace {

constexpr double kNodata = -32767;  // far below any seabed, exact in float32
constexpr const char* kDatumKey = "SEAMAP_HEIGHT_DATUM";
constexpr int kTilePx = 256;

void RegisterGdal() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

// GDAL's messages go to the exception, not to stderr.
struct QuietGdal {
  QuietGdal() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietGdal() { CPLPopErrorHandler(); }
};

std::string GdalMessage() {
  const char* m = CPLGetLastErrorMsg();
  return m && *m ? std::string(": ") + m : std::string();
}

struct DatasetCloser {
  void operator()(GDALDataset* ds) const {
    if (ds) GDALClose(ds);
  }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

std::string WktOf(const OGRSpatialReference& srs) {
  char* wkt = nullptr;
  srs.exportToWkt(&wkt);
  std::string out = wkt ? wkt : "";
  CPLFree(wkt);
  return out;
}

OGRSpatialReference LocalSrs(LatLon origin) {
  OGRSpatialReference srs;
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  srs.importFromProj4(LocalTmercProj4(origin).c_str());
  return srs;
}

OGRSpatialReference TargetSrs(HeightGridCrs crs, LatLon origin) {
  if (crs == HeightGridCrs::kLocalTmerc) return LocalSrs(origin);
  OGRSpatialReference srs;
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  srs.importFromEPSG(crs == HeightGridCrs::kUtm ? UtmZoneFor(origin).Epsg() : 3857);
  return srs;
}

// Runs GDALWarp (the gdalwarp program's engine) on `src` into an in-memory dataset.
Dataset WarpToMemory(GDALDataset* src, const std::vector<std::string>& args, const std::string& path) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  GDALWarpAppOptions* opts = GDALWarpAppOptionsNew(argv.data(), nullptr);
  GDALDatasetH source = GDALDataset::ToHandle(src);
  int usage_error = 0;
  GDALDatasetH out = GDALWarp("", nullptr, 1, &source, opts, &usage_error);
  GDALWarpAppOptionsFree(opts);
  if (!out) throw InputError(path, 0, "", "cannot reproject the height model" + GdalMessage());
  return Dataset(GDALDataset::FromHandle(out));
}

std::string Number(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

}  // namespace

std::string LocalTmercProj4(LatLon origin) {
  // As core/geo/local_frame.cc's projection (same ellipsoid, same digits);
  // +datum names WGS84 for GIS tools.
  std::ostringstream s;
  s.precision(17);
  s << "+proj=tmerc +lat_0=" << origin.lat << " +lon_0=" << origin.lon
    << " +k=1 +x_0=0 +y_0=0 +datum=WGS84 +units=m +no_defs";
  return s.str();
}

void WriteHeightGridGeotiff(const HeightGrid& grid, LatLon origin, const std::string& path,
                            const HeightGridGeotiffOptions& options) {
  if (grid.empty()) throw InputError(path, 0, "", "the height model is empty: nothing to write");
  const bool with_sigma = options.write_sigma;
  if (with_sigma && grid.sigma_m.size() != grid.height_m.size())
    throw InputError(path, 0, "sigma_m", "the height model has no uncertainty of its size to write");
  RegisterGdal();
  QuietGdal quiet;

  GDALDriver* mem_driver = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* tiff_driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!mem_driver || !tiff_driver) throw InputError(path, 0, "", "GDAL lacks the MEM or GTiff driver");
  const int bands = with_sigma ? 2 : 1;
  Dataset mem(mem_driver->Create("", grid.cols(), grid.rows(), bands, GDT_Float32, nullptr));
  if (!mem) throw InputError(path, 0, "", "cannot allocate the height raster" + GdalMessage());
  double gt[6] = {grid.east0_m - grid.cell_m / 2, grid.cell_m, 0, grid.north0_m + grid.cell_m / 2, 0, -grid.cell_m};
  mem->SetGeoTransform(gt);
  const OGRSpatialReference local = LocalSrs(origin);
  mem->SetSpatialRef(&local);
  for (int b = 0; b < bands; ++b) {
    cv::Mat1f values = (b == 0 ? grid.height_m : grid.sigma_m).clone();
    // NaN holes (and a height's NaN sigma) become nodata.
    for (int r = 0; r < values.rows; ++r)
      for (int c = 0; c < values.cols; ++c)
        if (!std::isfinite(values(r, c)) || !std::isfinite(grid.height_m(r, c)))
          values(r, c) = static_cast<float>(kNodata);
    GDALRasterBand* band = mem->GetRasterBand(b + 1);
    band->SetNoDataValue(kNodata);
    band->SetDescription(b == 0 ? "height_m" : "sigma_m");
    if (band->RasterIO(GF_Write, 0, 0, values.cols, values.rows, values.ptr<float>(), values.cols, values.rows,
                       GDT_Float32, 0, static_cast<GSpacing>(values.step[0]), nullptr) != CE_None)
      throw InputError(path, 0, "", "cannot fill the height raster" + GdalMessage());
  }
  mem->SetMetadataItem(kDatumKey, grid.has_depth_datum ? "sea_surface" : "vehicle");

  Dataset source = std::move(mem);
  if (options.crs != HeightGridCrs::kLocalTmerc) {
    const std::string wkt = WktOf(TargetSrs(options.crs, origin));
    // Keep about the grid's own cell size; square pixels.
    source = WarpToMemory(source.get(),
                          {"-of", "MEM", "-t_srs", wkt, "-r", "bilinear", "-srcnodata", Number(kNodata), "-dstnodata",
                           Number(kNodata), "-wo", "INIT_DEST=NO_DATA"},
                          path);
    source->SetMetadataItem(kDatumKey, grid.has_depth_datum ? "sea_surface" : "vehicle");
    for (int b = 0; b < bands; ++b) source->GetRasterBand(b + 1)->SetDescription(b == 0 ? "height_m" : "sigma_m");
  }

  std::error_code ec;
  std::filesystem::remove(path, ec);
  const std::string block = std::to_string(kTilePx);
  const std::vector<std::string> create = {"COMPRESS=DEFLATE", "PREDICTOR=3", "TILED=YES", "BLOCKXSIZE=" + block,
                                           "BLOCKYSIZE=" + block};
  std::vector<char*> create_options;
  for (const std::string& o : create) create_options.push_back(const_cast<char*>(o.c_str()));
  create_options.push_back(nullptr);
  {
    Dataset tiff(tiff_driver->CreateCopy(path.c_str(), source.get(), FALSE, create_options.data(), nullptr, nullptr));
    if (!tiff) throw InputError(path, 0, "", "cannot write the GeoTIFF" + GdalMessage());
  }
  const int width = source->GetRasterXSize(), height = source->GetRasterYSize();
  if (options.overviews && std::max(width, height) > kTilePx) {
    Dataset tiff(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE));
    if (!tiff) throw InputError(path, 0, "", "cannot reopen the GeoTIFF for its overviews" + GdalMessage());
    std::vector<int> levels;
    for (int f = 2; std::max(width, height) / f >= kTilePx / 2; f *= 2) levels.push_back(f);
    CPLSetThreadLocalConfigOption("COMPRESS_OVERVIEW", "DEFLATE");
    const CPLErr err = levels.empty() ? CE_None
                                      : tiff->BuildOverviews("AVERAGE", static_cast<int>(levels.size()), levels.data(),
                                                             0, nullptr, nullptr, nullptr);
    CPLSetThreadLocalConfigOption("COMPRESS_OVERVIEW", nullptr);
    if (err != CE_None) throw InputError(path, 0, "", "cannot build the GeoTIFF's overviews" + GdalMessage());
  }
}

HeightGrid ReadHeightGridGeotiff(const std::string& path, LatLon origin) {
  RegisterGdal();
  QuietGdal quiet;
  Dataset ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!ds)
    throw InputError(path, 0, "", "cannot read as a height raster (GeoTIFF or another GDAL format)" + GdalMessage());
  const int bands = ds->GetRasterCount();
  const bool has_sigma = bands == 2 && std::strcmp(ds->GetRasterBand(2)->GetDescription(), "sigma_m") == 0;
  if (bands != 1 && !has_sigma)
    throw InputError(path, 0, "", "expected a single-band height raster, found " + std::to_string(bands) + " bands");
  const OGRSpatialReference* srs = ds->GetSpatialRef();
  if (!srs || srs->IsEmpty())
    throw InputError(path, 0, "", "has no coordinate reference system: cannot place the heights on the map");
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None)
    throw InputError(path, 0, "", "has no georeference (geotransform): cannot place the heights on the map");
  const char* datum = ds->GetMetadataItem(kDatumKey);

  const OGRSpatialReference local = LocalSrs(origin);
  const bool same_grid =
      srs->IsSame(&local) && gt[2] == 0 && gt[4] == 0 && gt[1] > 0 && std::fabs(gt[5] + gt[1]) <= 1e-9 * gt[1];
  if (!same_grid) {
    ds = WarpToMemory(
        ds.get(),
        {"-of", "MEM", "-t_srs", WktOf(local), "-r", "bilinear", "-dstnodata", "nan", "-wo", "INIT_DEST=NO_DATA"},
        path);
    if (ds->GetGeoTransform(gt) != CE_None || gt[2] != 0 || gt[4] != 0)
      throw InputError(path, 0, "", "cannot reproject the heights onto a north-up grid");
  }

  HeightGrid grid;
  grid.cell_m = gt[1];
  grid.east0_m = gt[0] + gt[1] / 2;
  grid.north0_m = gt[3] + gt[5] / 2;
  grid.has_depth_datum = !(datum && std::strcmp(datum, "vehicle") == 0);
  const int cols = ds->GetRasterXSize(), rows = ds->GetRasterYSize();
  for (int b = 0; b < (has_sigma ? 2 : 1); ++b) {
    cv::Mat1f values(rows, cols);
    GDALRasterBand* band = ds->GetRasterBand(b + 1);
    if (band->RasterIO(GF_Read, 0, 0, cols, rows, values.ptr<float>(), cols, rows, GDT_Float32, 0,
                       static_cast<GSpacing>(values.step[0]), nullptr) != CE_None)
      throw InputError(path, 0, "", "cannot read the heights" + GdalMessage());
    int has_nodata = 0;
    const double nodata = band->GetNoDataValue(&has_nodata);
    if (has_nodata && std::isfinite(nodata)) {
      const float nd = static_cast<float>(nodata);
      for (int r = 0; r < rows; ++r)
        for (int c = 0; c < cols; ++c)
          if (values(r, c) == nd) values(r, c) = NAN;
    }
    (b == 0 ? grid.height_m : grid.sigma_m) = values;
  }
  if (!has_sigma) grid.sigma_m = cv::Mat1f(rows, cols, NAN);
  // A hole in the heights is a hole in the sigma too.
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      if (!std::isfinite(grid.height_m(r, c))) grid.sigma_m(r, c) = NAN;
  return grid;
}

}  // namespace seamap
