#pragma once
// What `serve` and `replay` can show beside the vehicle's track of a mission
// georeferenced by a towed GPS buoy (seamap georef): the buoy's fixes
// (--buoy buoy.csv) and the keyframes with the ones used in the fit
// (--georef-nav nav.csv). Read before serving, so bad input stops with its
// file and line.
#include <optional>
#include <string>
#include <vector>

#include "cli/args.h"
#include "core/tiles/mission_records.h"
#include "server/mission_state.h"

namespace seamap::cli {

extern const char* kGeorefOverlayHelp;

struct GeorefOverlays {
  std::optional<std::string> buoy_file, nav_file;
  std::vector<TrackPoint> buoy_track;
  std::vector<server::GeorefKeyframe> keyframes;

  bool any() const { return buoy_file || nav_file; }
  void ApplyTo(server::MissionState& mission) const;
};

GeorefOverlays ReadGeorefOverlays(Args& args);

}  // namespace seamap::cli
