#include "cli/georef_overlays.h"

#include <cmath>
#include <cstdio>
#include <fstream>

#include "core/georef/georef_inputs.h"
#include "core/nav/csv_numbers.h"
#include "core/util/error.h"

namespace seamap::cli {

const char* kGeorefOverlayHelp =
    "  --buoy FILE         a towed GPS buoy's fixes (time_s,lat,lon; seamap georef's --buoy), served\n"
    "                      as GET /api/track?source=buoy and drawn beside the vehicle's track\n"
    "  --georef-nav FILE   seamap georef's nav.csv: its keyframes on the map, those used in the fit\n"
    "                      marked (GET /api/keyframes)\n";

GeorefOverlays ReadGeorefOverlays(Args& args) {
  GeorefOverlays o;
  o.buoy_file = args.Get("buoy");
  o.nav_file = args.Get("georef-nav");
  if (o.buoy_file) {
    const BuoyLog log = ReadBuoyLog(*o.buoy_file);
    for (const auto& r : log.rejected) std::fprintf(stderr, "skipped: %s\n", r.Message().c_str());
    for (const auto& f : log.fixes) {
      TrackPoint point;
      point.time_s = f.time_s;
      point.position = f.position;
      o.buoy_track.push_back(point);
    }
  }
  if (o.nav_file) {
    int row_number = 0;
    // sigma_m (each keyframe's predicted error) is optional: older nav.csv files lack it.
    std::vector<std::string> columns{"time_s", "lat", "lon", "good"};
    std::string header;
    std::ifstream nav(*o.nav_file);
    std::getline(nav, header);
    if (header.find("sigma_m") != std::string::npos) columns.push_back("sigma_m");
    for (const CsvNumbers& row : ReadCsvNumbers(*o.nav_file, columns)) {
      ++row_number;
      const LatLon at{row.at("lat"), row.at("lon")};
      if (std::abs(at.lat) > 90 || std::abs(at.lon) > 180)
        throw InputError(*o.nav_file, 0, "lat,lon", "off the globe in data row " + std::to_string(row_number));
      o.keyframes.push_back({row.at("time_s"), at, row.at("good") != 0, row.count("sigma_m") ? row.at("sigma_m") : 0});
    }
  }
  return o;
}

void GeorefOverlays::ApplyTo(server::MissionState& mission) const {
  mission.SetBuoyTrack(buoy_track);
  mission.SetKeyframes(keyframes);
}

}  // namespace seamap::cli
