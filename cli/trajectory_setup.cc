#include "cli/trajectory_setup.h"

#include <opencv2/imgcodecs.hpp>

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

cv::Mat ReadFrameForFeatures(const std::string& path, int64_t max_pixels) {
  std::string problem;
  const auto header = ReadImageHeader(path, &problem);
  if (!header || TooLargeToDecode(*header, max_pixels)) return cv::Mat();
  try {
    return cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    return cv::Mat();
  }
}

}  // namespace seamap::cli
