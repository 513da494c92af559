#include "core/export/dem_export.h"

#include <cpl_conv.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <vector>

#include "core/terrain/height_datum.h"
#include "core/terrain/height_grid_io.h"
#include "core/util/error.h"

namespace seamap {
namespace {

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(d); }
};
using Dataset = std::unique_ptr<GDALDataset, DatasetCloser>;

// The local frame as a projected CRS (LocalFrame's definition, as truth/terrain.tif has it).
std::string LocalFrameWkt(LatLon origin) {
  const std::string proj = LocalTmercProj4(origin);
  OGRSpatialReference srs;
  if (srs.importFromProj4(proj.c_str()) != OGRERR_NONE)
    throw std::runtime_error("GDAL cannot express the mission's local frame: " + proj);
  char* wkt = nullptr;
  srs.exportToWkt(&wkt);
  std::string out = wkt ? wkt : "";
  CPLFree(wkt);
  return out;
}

}  // namespace

DemSummary ExportDem(const MissionTerrain& terrain, const std::string& path) {
  const HeightGrid& g = terrain.grid;
  if (g.empty()) throw InputError(path, 0, "terrain", "the height model is empty");
  const HeightDatum datum = UserDatum(g);
  DemSummary s;
  s.width_px = g.cols();
  s.height_px = g.rows();
  s.cell_m = g.cell_m;
  s.datum = datum.name;

  std::vector<float> cells(static_cast<size_t>(g.rows()) * g.cols());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int r = 0; r < g.rows(); ++r)
    for (int c = 0; c < g.cols(); ++c) {
      const float h = g.height_m(r, c);
      float& out = cells[static_cast<size_t>(r) * g.cols() + c];
      if (!std::isfinite(h)) {
        out = static_cast<float>(kDemNodata);
        continue;
      }
      out = static_cast<float>(h + datum.offset_m);
      lo = std::min<double>(lo, out);
      hi = std::max<double>(hi, out);
    }
  if (std::isfinite(lo)) {
    s.min_m = lo;
    s.max_m = hi;
  }

  GDALAllRegister();
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* cog = GetGDALDriverManager()->GetDriverByName("COG");
  if (!mem || !cog) throw std::runtime_error("GDAL has no MEM or COG driver (GDAL >= 3.1 needed)");
  Dataset model(mem->Create("", g.cols(), g.rows(), 1, GDT_Float32, nullptr));
  if (!model) throw std::runtime_error("GDAL cannot hold the height model in memory");
  // Cell centres are at east0 + col * cell: the raster's corner is half a cell out.
  double transform[6] = {g.east0_m - 0.5 * g.cell_m, g.cell_m, 0, g.north0_m + 0.5 * g.cell_m, 0, -g.cell_m};
  model->SetGeoTransform(transform);
  model->SetProjection(LocalFrameWkt(terrain.origin).c_str());
  model->SetMetadataItem("SEAMAP_HEIGHT_DATUM", datum.name.c_str());
  model->SetMetadataItem("SEAMAP_HEIGHT", datum.name == "sea_surface" ? "metres up from the sea surface"
                                                                      : "metres up from the survey's mean seabed");
  GDALRasterBand* band = model->GetRasterBand(1);
  band->SetNoDataValue(kDemNodata);
  band->SetUnitType("m");
  band->SetDescription(("height_m (" + datum.name + ")").c_str());
  if (band->RasterIO(GF_Write, 0, 0, g.cols(), g.rows(), cells.data(), g.cols(), g.rows(), GDT_Float32, 0, 0) !=
      CE_None)
    throw std::runtime_error("GDAL cannot hold the height model in memory");
  std::vector<int> levels;
  for (int f = 2; (std::max(g.rows(), g.cols()) + f - 1) / f >= 32; f *= 2) levels.push_back(f);
  if (!levels.empty() && model->BuildOverviews("AVERAGE", static_cast<int>(levels.size()), levels.data(), 0, nullptr,
                                               nullptr, nullptr) != CE_None)
    throw std::runtime_error("GDAL cannot build the height model's overviews");
  s.overviews = static_cast<int>(levels.size());

  const std::string tmp = path + ".part";
  const char* options[] = {"COMPRESS=DEFLATE", "PREDICTOR=FLOATING_POINT", "BLOCKSIZE=256",
                           "OVERVIEWS=FORCE_USE_EXISTING", nullptr};
  CPLErrorReset();
  CPLPushErrorHandler(CPLQuietErrorHandler);  // the message goes into our InputError instead
  Dataset out(cog->CreateCopy(tmp.c_str(), model.get(), FALSE, const_cast<char**>(options), nullptr, nullptr));
  CPLPopErrorHandler();
  const std::string why = CPLGetLastErrorMsg();
  if (!out) {
    VSIUnlink(tmp.c_str());
    throw InputError(path, 0, "output", "GDAL could not write the DEM: " + (why.empty() ? "unknown error" : why));
  }
  out.reset();
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError(path, 0, "output", "cannot write the DEM: " + ec.message());
  }
  return s;
}

}  // namespace seamap
