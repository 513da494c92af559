// seamap enhance IN OUT [--ops LIST | --config FILE]
// seamap enhance-report DIR [--ops LIST[;LIST...]] [--config FILE] [--max-frames N] [--detector sift|orb]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/enhance/enhance_chain.h"
#include "core/enhance/feature_report.h"
#include "core/image/image_read.h"
#include "core/util/error.h"
#include "core/util/json_file.h"

namespace seamap::cli {
namespace {
namespace fs = std::filesystem;

// A chain file is either {"ops": [...]} or a build config holding it under "enhance".
EnhanceChain LoadChainFile(const std::string& path) {
  nlohmann::json config = ReadJsonFile(path, "enhancement config");
  if (config.is_object() && config.contains("enhance")) return EnhanceChain::FromJson(config["enhance"], path);
  return EnhanceChain::FromJson(config, path);
}

cv::Mat ReadImage(const std::string& path) {
  std::string problem;
  cv::Mat image = ReadGuardedImage(path, &problem);
  if (image.empty()) throw InputError(path, 0, "", "cannot read the image: " + problem);
  return image;
}

// Runs f, re-raising an operation's InputError with the image path as its file.
template <typename F>
auto ForImage(const std::string& path, F f) {
  try {
    return f();
  } catch (const InputError& e) {
    if (!e.file().empty()) throw;
    throw InputError(path, 0, e.field(), e.detail());
  }
}

bool IsImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".tiff" || ext == ".bmp";
}

std::vector<std::string> SplitLists(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find(';', start);
    if (end == std::string::npos) end = text.size();
    out.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

}  // namespace

int RunEnhance(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help"});
  if (args.Flag("help")) {
    std::puts(
        "usage: seamap enhance IN OUT [--ops LIST | --config FILE]\n"
        "  --ops LIST     op[:param=value...],op...  (default: flatfield,dehaze:gate=false,clahe:clip_limit=3)\n"
        "  --config FILE  {\"ops\": [...]} or a build config with \"enhance\"");
    return 0;
  }
  auto ops = args.Get("ops");
  auto config = args.Get("config");
  args.RejectUnknown();
  if (args.positionals().size() != 2)
    throw InputError("", 0, "",
                     "usage: seamap enhance IN OUT [--ops LIST | --config FILE] (expected 2 paths, got " +
                         std::to_string(args.positionals().size()) + ")");
  if (ops && config) throw InputError("", 0, "--config", "give either --ops or --config, not both");
  const std::string in = args.positionals()[0], out = args.positionals()[1];
  EnhanceChain chain = ops      ? EnhanceChain::FromOpList(*ops, "--ops")
                       : config ? LoadChainFile(*config)
                                : EnhanceChain::Default();

  cv::Mat image = ReadImage(in);
  auto start = std::chrono::steady_clock::now();
  cv::Mat enhanced = ForImage(in, [&] { return chain.Apply(image); });  // a flat field learns from this frame alone
  double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  bool written = false;
  try {
    written = cv::imwrite(out, enhanced);
  } catch (const cv::Exception& e) {
    throw InputError(out, 0, "", "cannot write the image: " + e.msg);
  }
  if (!written)
    throw InputError(out, 0, "", "cannot write the image (expected a writable .png, .jpg, .tif or .bmp path)");
  std::printf("%s -> %s (%dx%d, %s) in %.1f ms\nchain: %s\n", in.c_str(), out.c_str(), image.cols, image.rows,
              cv::typeToString(image.type()).c_str(), ms, chain.Describe().c_str());
  return 0;
}

int RunEnhanceReport(int argc, char** argv, int first) {
  // Time the chains on one core, as the build runs them (one frame per worker).
  cv::setNumThreads(1);
  Args args(argc, argv, first, {"help"});
  if (args.Flag("help")) {
    std::puts(
        "usage: seamap enhance-report DIR [--ops LIST[;LIST...]] [--config FILE] [--max-frames N] "
        "[--detector sift|orb]\n"
        "  features, matches and RANSAC inliers between consecutive frames before and after each chain");
    return 0;
  }
  auto ops = args.Get("ops");
  auto config = args.Get("config");
  const int max_frames = args.GetInt("max-frames", 50);
  const std::string detector_name = args.GetOr("detector", "sift");
  args.RejectUnknown();
  if (args.positionals().size() != 1)
    throw InputError("", 0, "",
                     "usage: seamap enhance-report DIR [--ops LIST[;LIST...]] [--config FILE] "
                     "[--max-frames N] [--detector sift|orb]");
  if (max_frames < 2)
    throw InputError("", 0, "--max-frames", "expected a whole number >= 2, got " + std::to_string(max_frames));
  const FeatureDetector detector = ParseFeatureDetector(detector_name, "--detector");
  const fs::path dir = args.positionals()[0];
  if (!fs::is_directory(dir)) throw InputError(dir.string(), 0, "", "expected a folder of survey photos");

  // Chains: each op alone and the default, unless --ops / --config choose.
  std::vector<EnhanceChain> chains;
  if (ops)
    for (const std::string& list : SplitLists(*ops)) chains.push_back(EnhanceChain::FromOpList(list, "--ops"));
  if (config) chains.push_back(LoadChainFile(*config));
  if (chains.empty()) {
    for (const std::string& name : EnhanceOpNames()) chains.push_back(EnhanceChain::FromOpList(name, "report"));
    chains.push_back(EnhanceChain::Default());
  }

  std::vector<fs::path> paths;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && IsImageFile(entry.path())) paths.push_back(entry.path());
  std::sort(paths.begin(), paths.end());  // survey photos are named in capture order
  if (paths.size() > static_cast<size_t>(max_frames)) paths.resize(max_frames);
  if (paths.size() < 2)
    throw InputError(dir.string(), 0, "",
                     "expected at least 2 images (.png, .jpg, .tif, .bmp), found " + std::to_string(paths.size()));
  std::vector<cv::Mat> frames;
  for (const auto& p : paths) frames.push_back(ReadImage(p.string()));

  std::printf("%zu frames from %s (%dx%d, %s), detector %s\n", frames.size(), dir.string().c_str(), frames[0].cols,
              frames[0].rows, cv::typeToString(frames[0].type()).c_str(), detector_name.c_str());
  const FeatureStats before = MeasureFeatures(frames, detector);
  std::vector<ChainReport> rows;
  for (const EnhanceChain& chain : chains)
    rows.push_back(ForImage(dir.string(), [&] { return ReportChain(chain, frames, detector, &before); }));
  std::fputs(FormatReportTable(rows, detector_name).c_str(), stdout);
  auto best = std::max_element(rows.begin(), rows.end(), [](const ChainReport& a, const ChainReport& b) {
    return a.after.inliers < b.after.inliers;
  });
  std::printf("most homography inliers per pair: %s (%.1f -> %.1f)\n", best->chain.c_str(), best->before.inliers,
              best->after.inliers);
  return 0;
}

}  // namespace seamap::cli
