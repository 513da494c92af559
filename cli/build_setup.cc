#include "cli/build_setup.h"

#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "core/enhance/enhance_chain.h"
#include "core/mosaic/frame_image.h"
#include "core/nav/nav_reader.h"
#include "core/util/error.h"
#include "server/server_options.h"

namespace seamap::cli {
namespace fs = std::filesystem;

namespace {

// Gray or colour mosaic, from the first frame that can be read.
int ProbeChannels(const FrameList& frames) {
  for (const auto& f : frames.frames) {
    std::error_code ec;
    if (!fs::is_regular_file(f.image_path, ec)) continue;
    cv::Mat m = cv::imread(f.image_path, cv::IMREAD_UNCHANGED);
    if (!m.empty()) return m.channels() >= 3 ? 3 : 1;
  }
  return 1;
}

}  // namespace

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
  in.channels = ProbeChannels(in.frames);
  return in;
}

BuildHooks MakeHooks(const BuildInputs& in) {
  BuildHooks hooks;
  if (!in.config.enhance || in.config.layers == "raw") return hooks;
  auto chain = std::make_shared<EnhanceChain>(EnhanceChain::FromJson(*in.config.enhance, in.config_source));
  // Stateful ops (the flat field) learn from the survey's first frames.
  std::vector<cv::Mat> samples;
  for (const auto& f : in.frames.frames) {
    if (static_cast<int>(samples.size()) >= chain->SeedFrames()) break;
    std::error_code ec;
    if (!fs::is_regular_file(f.image_path, ec)) continue;
    cv::Mat m = cv::imread(f.image_path, cv::IMREAD_UNCHANGED);
    if (!m.empty() && m.cols == in.camera.width && m.rows == in.camera.height)
      samples.push_back(ToEightBit(m, in.channels, in.config.frames.sixteen_bit_white));
  }
  if (!samples.empty()) chain->Seed(samples);
  hooks.preprocess = [chain](const cv::Mat& frame) { return chain->Apply(frame); };
  return hooks;
}

}  // namespace seamap::cli
