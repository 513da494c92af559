#include "cli/stereo_setup.h"

#include <cmath>
#include <cstdio>

#include "core/util/error.h"

namespace seamap::cli {

RigMount ReadRigMount(Args& args) {
  RigMount mount;
  mount.looking = ParseLooking(args.GetOr("rig", "forward"), "--rig");
  if (auto text = args.Get("rig-offset")) {
    double x = 0, y = 0, z = 0;
    char end = 0;
    if (std::sscanf(text->c_str(), "%lf,%lf,%lf%c", &x, &y, &z, &end) != 3 || !std::isfinite(x + y + z) ||
        std::abs(x) + std::abs(y) + std::abs(z) > 100)
      throw InputError("", 0, "--rig-offset", "expected X,Y,Z in metres (each within 100 m), got '" + *text + "'");
    mount.offset_m = {x, y, z};
  }
  return mount;
}

}  // namespace seamap::cli
