#include "cli/trajectory_setup.h"

namespace seamap::cli {

const char* kNavigationNoiseHelp =
    "  --nav-noise M       the navigation's white position noise, 1 sigma (default 0.05; config navigation.noise_m)\n"
    "  --nav-drift M_MIN   its drift rate, metres per minute (default 1; navigation.drift_m_per_min)\n"
    "  --heading-noise DEG its heading noise (default 1; navigation.heading_noise_deg)\n";

RefineOptions ReadRefineOptions(Args& args, const NavigationSettings& settings, int threads) {
  RefineOptions o;
  o.nav_noise_m = args.GetDouble("nav-noise", settings.noise_m);
  o.nav_drift_m_per_min = args.GetDouble("nav-drift", settings.drift_m_per_min);
  o.heading_noise_deg = args.GetDouble("heading-noise", settings.heading_noise_deg);
  o.threads = threads;
  o.Check();
  return o;
}

}  // namespace seamap::cli
