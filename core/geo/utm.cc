#include "core/geo/utm.h"

#include <proj.h>

#include <cmath>
#include <stdexcept>

#include "core/util/error.h"

namespace seamap {
namespace {
constexpr double kDeg = M_PI / 180.0;
}  // namespace

UtmZoneId UtmZoneFor(LatLon p) {
  int zone = static_cast<int>(std::floor((p.lon + 180.0) / 6.0)) + 1;
  if (zone > 60) zone = 60;                                              // lon = 180
  if (p.lat >= 56 && p.lat < 64 && p.lon >= 3 && p.lon < 12) zone = 32;  // band V, Norway
  if (p.lat >= 72 && p.lat <= 84 && p.lon >= 0 && p.lon < 42) {          // band X, Svalbard
    zone = p.lon < 9 ? 31 : p.lon < 21 ? 33 : p.lon < 33 ? 35 : 37;
  }
  return {zone, p.lat >= 0};
}

struct UtmProjection::Proj {
  PJ_CONTEXT* ctx = nullptr;
  PJ* op = nullptr;
  ~Proj() {
    if (op) proj_destroy(op);
    if (ctx) proj_context_destroy(ctx);
  }
};

UtmProjection::UtmProjection(UtmZoneId zone) : zone_(zone), proj_(std::make_unique<Proj>()) {
  if (zone.zone < 1 || zone.zone > 60)
    throw InputError("", 0, "utm_zone", "expected a UTM zone 1..60, got " + std::to_string(zone.zone));
  const std::string definition =
      "+proj=utm +zone=" + std::to_string(zone.zone) + (zone.north ? "" : " +south") + " +ellps=WGS84 +units=m";
  proj_->ctx = proj_context_create();
  proj_->op = proj_create(proj_->ctx, definition.c_str());
  if (!proj_->op) throw std::runtime_error("PROJ cannot create '" + definition + "'");
}

UtmProjection::~UtmProjection() = default;

UtmXY UtmProjection::Forward(LatLon p) const {
  const PJ_COORD c = proj_trans(proj_->op, PJ_FWD, proj_coord(p.lon * kDeg, p.lat * kDeg, 0, 0));
  return {c.xy.x, c.xy.y};
}

LatLon UtmProjection::Inverse(UtmXY xy) const {
  const PJ_COORD c = proj_trans(proj_->op, PJ_INV, proj_coord(xy.easting, xy.northing, 0, 0));
  return {c.lp.phi / kDeg, c.lp.lam / kDeg};
}

}  // namespace seamap
