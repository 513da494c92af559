#include "tests/integration/survey_fixture.h"

#include <filesystem>
#include <map>
#include <memory>

#include <unistd.h>

namespace seamap::testing {

std::string SimulatedSurvey::BuildArgs() const {
  return "build --images " + photo + " --nav " + nav + " --camera " + camera + " --origin " + origin + " --quiet";
}

int Seamap(const std::string& args, std::string* out) {
  return RunCommand(SeamapBinary() + " " + args, out);
}

const SimulatedSurvey& SharedSurvey(const std::string& name, const std::string& extra) {
  static std::map<std::string, std::unique_ptr<SimulatedSurvey>> cache;
  static std::filesystem::path root = [] {
    auto p = std::filesystem::temp_directory_path() / ("seamap_it_" + std::to_string(::getpid()));
    std::filesystem::create_directories(p);
    std::atexit([] {
      std::error_code ec;
      if (!std::getenv("SEAMAP_KEEP_TEST_FILES"))
        std::filesystem::remove_all(
            std::filesystem::temp_directory_path() / ("seamap_it_" + std::to_string(::getpid())), ec);
    });
    return p;
  }();
  // One name, one survey: a second test reusing a name with other options
  // would silently get the first one's survey.
  static std::map<std::string, std::string> options_of;
  const auto [known, first] = options_of.emplace(name, extra);
  if (!first && known->second != extra)
    ADD_FAILURE() << "SharedSurvey(\"" << name << "\") asked for again with other options: \"" << known->second
                  << "\" and \"" << extra << "\"";
  auto& slot = cache[name];
  if (!slot) {
    slot = std::make_unique<SimulatedSurvey>();
    slot->dir = (root / name).string();
    slot->photo = slot->dir + "/photo";
    slot->nav = slot->dir + "/nav.csv";
    slot->camera = slot->dir + "/camera.json";
    std::string out;
    int rc = Seamap("simulate --out " + slot->dir + " " + extra, &out);
    if (rc != 0) ADD_FAILURE() << "simulate failed (" << rc << "):\n" << out;
  }
  return *slot;
}

const SimulatedSurvey& DriftingSurvey() {
  return SharedSurvey("drifting",
                      "--frames 160 --line-length 6 --line-spacing 0.9 --nav-drift 0.5 --nav-noise 0.005 "
                      "--heading-noise 0.5 --image-format jpg --seed 4 --quiet");
}

}  // namespace seamap::testing
