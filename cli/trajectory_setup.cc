#include "cli/trajectory_setup.h"

#include "core/util/error.h"

namespace seamap::cli {

const char* kNavigationNoiseHelp =
    "  --nav-noise M       the navigation's white position noise, 1 sigma (default 0.05; config navigation.noise_m)\n"
    "  --nav-drift M_MIN   its drift rate, metres per minute (default 1; navigation.drift_m_per_min)\n"
    "  --heading-noise DEG its heading noise (default 1; navigation.heading_noise_deg)\n"
    "  --refine-method M   refine's solve: auto (default: bundle where the navigation's depth + altitude\n"
    "                      shows relief, else planar), planar (the 2-D pose graph) or bundle (3-D poses\n"
    "                      and seabed points; slower, docs/TERRAIN.md)\n"
    "  --attitude-noise DEG  the pitch/roll sensor's noise for the bundle (default 0.5)\n"
    "  --bundle-window N   a longer survey's bundle is solved N frames at a time, each window holding the\n"
    "                      frames before it fixed (default 0: one bundle up to 450 frames, windows of\n"
    "                      300 past that)\n";

const char* kFeatureEnhanceHelp =
    "  --feature-enhance off|auto|LIST  enhance the frames before their features are detected (seed 004;\n"
    "                      LIST as seamap enhance --ops): auto tries a few chains on the first frames and keeps\n"
    "                      the one that raises the inliers between frames, if any (default off)\n";

RefineOptions ReadRefineOptions(Args& args, const NavigationSettings& settings, int threads) {
  RefineOptions o;
  o.nav_noise_m = args.GetDouble("nav-noise", settings.noise_m);
  o.nav_drift_m_per_min = args.GetDouble("nav-drift", settings.drift_m_per_min);
  o.heading_noise_deg = args.GetDouble("heading-noise", settings.heading_noise_deg);
  o.threads = threads;
  if (const auto method = args.Get("refine-method")) {
    if (*method == "bundle")
      o.method = RefineMethod::kBundle;
    else if (*method == "planar")
      o.method = RefineMethod::kPlanar;
    else if (*method == "auto")
      o.method = RefineMethod::kAuto;
    else
      throw InputError("", 0, "--refine-method",
                       "expected auto, bundle or planar, got '" + method->substr(0, 100) + "'");
  }
  o.attitude_noise_deg = args.GetDouble("attitude-noise", o.attitude_noise_deg);
  o.bundle_window_frames = args.GetInt("bundle-window", o.bundle_window_frames);
  o.Check();
  return o;
}

}  // namespace seamap::cli
