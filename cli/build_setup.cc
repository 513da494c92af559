#include "cli/build_setup.h"

#include <algorithm>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "core/enhance/enhance_chain.h"
#include "core/mosaic/frame_image.h"
#include "core/mosaic/mosaic_plan.h"
#include "core/mosaic/survey_channels.h"
#include "core/nav/nav_reader.h"
#include "core/util/error.h"
#include "server/server_options.h"

namespace seamap::cli {
namespace fs = std::filesystem;

BuildInputs ReadBuildInputs(Args& args) {
  BuildInputs in;
  if (auto path = args.Get("config")) {
    in.config = LoadBuildConfig(*path);
    in.config_source = *path;
    // The "server" object is the server's to read; a mistake in it is
    // reported whichever command reads the file.
    if (in.config.server) server::ServerOptions::FromJson(*in.config.server, *path);
  }
  if (auto ops = args.Get("enhance")) {
    in.config.enhance = EnhanceChain::FromOpList(*ops, "--enhance").ToJson();
    if (in.config.layers == "raw") in.config.layers = "enhanced";
  }
  nlohmann::json overrides = nlohmann::json::object();
  if (auto v = args.Get("tile-format")) overrides["tile_format"] = *v;
  if (auto v = args.Get("name")) overrides["name"] = *v;
  for (const char* key : {"tile-size", "base-zoom", "min-zoom", "threads"}) {
    std::string k = key;
    if (args.Get(k)) {
      std::string json_key = k;
      for (char& c : json_key)
        if (c == '-') c = '_';
      overrides[json_key] = args.GetInt(k, 0);
    }
  }
  ApplyBuildConfig(overrides, "command line", &in.config);
  if (auto v = args.Get("origin")) {
    LatLonArg o = ParseLatLon(*v, "--origin");
    in.config.nav.origin = LatLon{o.lat, o.lon};
  }
  if (auto v = args.Get("utm-zone")) in.config.nav.utm_zone = args.GetInt("utm-zone", 0);

  in.camera = LoadCamera(args.Require("camera"));
  const std::string images = args.Require("images");
  std::error_code ec;
  if (!fs::is_directory(images, ec)) throw InputError(images, 0, "--images", "is not a folder of photos");
  NavTable nav = ReadNavigation(args.Require("nav"), in.config.nav);
  in.frame = LocalFrame(nav.origin);
  std::optional<std::string> image_times = args.Get("image-times");
  in.frames = MatchFrames(nav, images, image_times);
  in.warnings = nav.warnings;
  in.warnings.insert(in.warnings.end(), in.frames.warnings.begin(), in.frames.warnings.end());
  in.frames.rejected.insert(in.frames.rejected.begin(), nav.rejected.begin(), nav.rejected.end());
  const SurveyChannels channels = DecideChannels(in.frames.frames, in.config.frames.max_image_pixels);
  in.channels = channels.channels;
  if (!channels.warning.empty()) in.warnings.push_back(channels.warning);
  return in;
}

void CheckMemoryFits(const BuildInputs& in) {
  const MosaicPlan plan = PlanMosaic(in.config.map, in.camera, in.frame, in.frames.frames, in.channels);
  int cap_mb = in.config.buffer.memory_cap_mb;
  if (in.config.layers == "both" && in.config.enhance) cap_mb = std::max(16, cap_mb / 2);  // two builders share it
  CheckPlanFitsMemory(plan, in.camera, in.config.map.tile_size, cap_mb,
                      in.config_source == "build config" ? "" : in.config_source);
}

BuildHooks MakeHooks(const BuildInputs& in) {
  BuildHooks hooks;
  if (!in.config.enhance || in.config.layers == "raw") return hooks;
  auto chain = std::make_shared<EnhanceChain>(EnhanceChain::FromJson(*in.config.enhance, in.config_source));
  // Stateful ops (the flat field) learn from the survey's first frames.
  std::vector<cv::Mat> samples;
  for (const auto& f : in.frames.frames) {
    if (static_cast<int>(samples.size()) >= chain->SeedFrames()) break;
    // Read as the build reads frames: FIFOs and oversized images are left out.
    std::string problem;
    auto image = FrameImage::Read(f.image_path, in.channels, in.config.frames.sixteen_bit_white, &problem,
                                  in.config.frames.max_image_pixels);
    if (image && image->width() == in.camera.width && image->height() == in.camera.height) {
      try {
        samples.push_back(image->Full().clone());
      } catch (const InputError&) {  // broken JPEG data: the build reports it
      }
    }
  }
  if (!samples.empty()) chain->Seed(samples);
  hooks.preprocess = [chain](const cv::Mat& frame) { return chain->Apply(frame); };
  return hooks;
}

}  // namespace seamap::cli
