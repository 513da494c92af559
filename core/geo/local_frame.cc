#include "core/geo/local_frame.h"

#include <proj.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/util/error.h"

namespace seamap {
namespace {

// A PROJ context + operation pair; input/output of a +proj operation in
// PROJ's convention: geographic as (lon, lat) in radians, projected in metres.
struct ProjOperation {
  PJ_CONTEXT* ctx = nullptr;
  PJ* op = nullptr;
  explicit ProjOperation(const std::string& definition) {
    ctx = proj_context_create();
    op = proj_create(ctx, definition.c_str());
    if (!op) {
      std::string why = proj_context_errno_string(ctx, proj_context_errno(ctx));
      proj_context_destroy(ctx);
      throw std::runtime_error("PROJ cannot create '" + definition + "': " + why);
    }
  }
  ~ProjOperation() {
    proj_destroy(op);
    proj_context_destroy(ctx);
  }
  ProjOperation(const ProjOperation&) = delete;
  ProjOperation& operator=(const ProjOperation&) = delete;

  PJ_COORD Run(PJ_DIRECTION dir, double a, double b) const {
    PJ_COORD in = proj_coord(a, b, 0, 0);
    return proj_trans(op, dir, in);
  }
};

std::string TransverseMercatorAt(LatLon o) {
  std::ostringstream s;
  s.precision(17);
  s << "+proj=tmerc +lat_0=" << o.lat << " +lon_0=" << o.lon << " +k=1 +x_0=0 +y_0=0 +ellps=WGS84 +units=m";
  return s.str();
}

void CheckOrigin(LatLon o) {
  if (!std::isfinite(o.lat) || !std::isfinite(o.lon) || std::fabs(o.lat) > 90 || std::fabs(o.lon) > 180) {
    std::ostringstream s;
    s << "origin must be a latitude within [-90, 90] and a longitude within [-180, 180], got " << o.lat << "," << o.lon;
    throw InputError("--origin", 0, "", s.str());
  }
}

constexpr double kDeg = M_PI / 180.0;
}  // namespace

struct LocalFrame::Proj {
  explicit Proj(LatLon origin) : tmerc(TransverseMercatorAt(origin)) {}
  ProjOperation tmerc;
};

LocalFrame::LocalFrame(LatLon origin) : origin_(origin) {
  CheckOrigin(origin);
  proj_ = std::make_unique<Proj>(origin);
}

LocalFrame::~LocalFrame() = default;

LocalFrame::LocalFrame(const LocalFrame& other)
    : origin_(other.origin_), proj_(std::make_unique<Proj>(other.origin_)) {}

LocalFrame& LocalFrame::operator=(const LocalFrame& other) {
  if (this != &other) {
    std::lock_guard<std::mutex> lock(mutex_);
    origin_ = other.origin_;
    proj_ = std::make_unique<Proj>(other.origin_);
  }
  return *this;
}

LatLon LocalFrame::ToLatLon(LocalXY xy) const {
  std::lock_guard<std::mutex> lock(mutex_);
  PJ_COORD c = proj_->tmerc.Run(PJ_INV, xy.east, xy.north);
  return {c.lp.phi / kDeg, c.lp.lam / kDeg};
}

LocalXY LocalFrame::FromLatLon(LatLon ll) const {
  std::lock_guard<std::mutex> lock(mutex_);
  PJ_COORD c = proj_->tmerc.Run(PJ_FWD, ll.lon * kDeg, ll.lat * kDeg);
  return {c.xy.x, c.xy.y};
}

LatLon UtmToLatLon(double easting, double northing, int zone, bool north) {
  if (zone < 1 || zone > 60)
    throw InputError("", 0, "utm_zone", "expected a UTM zone 1..60, got " + std::to_string(zone));
  ProjOperation utm("+proj=utm +zone=" + std::to_string(zone) + (north ? "" : " +south") + " +ellps=WGS84 +units=m");
  PJ_COORD c = utm.Run(PJ_INV, easting, northing);
  if (!std::isfinite(c.lp.phi) || !std::isfinite(c.lp.lam) || c.lp.phi == HUGE_VAL)
    throw InputError("", 0, "easting/northing", "UTM coordinates do not map to a position");
  return {c.lp.phi / kDeg, c.lp.lam / kDeg};
}

}  // namespace seamap
