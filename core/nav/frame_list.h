#pragma once
// Pairs images with poses. When the navigation names images, each such record
// is a frame. When navigation is a time series and the images carry times
// (an image-times CSV with columns image,time_s), poses are interpolated to
// the image times (NavSeries, nav_series.h). Images outside the navigation's
// time span are rejected.
#include <optional>
#include <string>
#include <vector>

#include "core/camera/vehicle_pose.h"
#include "core/nav/nav_table.h"

namespace seamap {

struct FrameSpec {
  int index = 0;           // 0-based order of acquisition
  std::string image_path;  // images_dir / image
  std::string image;       // name as given
  std::optional<double> time_s;
  VehiclePose pose;  // where the frame is placed
  // The navigation's pose when `pose` is a corrected one (a refined or
  // filtered trajectory); the mission keeps both.
  std::optional<VehiclePose> nav_pose;
  int nav_line = 0;  // source line (0 when interpolated)
};

struct FrameList {
  std::vector<FrameSpec> frames;
  std::vector<Rejection> rejected;
  std::vector<std::string> warnings;  // e.g. image times given but not needed
};

FrameList MatchFrames(const NavTable& nav, const std::string& images_dir,
                      const std::optional<std::string>& image_times_csv);

}  // namespace seamap
