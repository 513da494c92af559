// seamap review MAP --truth SURVEY: a simulated survey's truth as the
// operator's review (confirm, reject, mark missed objects with a box), so a
// reviewed mission for training is made reproducibly (issue 32).
#include <cstdio>
#include <filesystem>
#include <string>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/mission/truth_review.h"
#include "core/tiles/tile_store.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kHelp =
    "usage: seamap review MAP --truth SURVEY\n"
    "\n"
    "Reviews MAP's recogniser detections against a simulated survey's truth, as an\n"
    "operator would in the console: a detection within max(10 cm, a quarter of the\n"
    "object's size) of a truth object of its class is confirmed, any other rejected,\n"
    "and each truth object no detection found becomes an operator's mark with its box.\n"
    "Detections already confirmed or rejected stay as they are. For training data\n"
    "(seamap training-data) and its tests; a real mission is reviewed in the console.\n"
    "\n"
    "  --truth SURVEY    the simulate --out folder (or its truth/objects.json)\n";

}  // namespace

int RunReview(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help"});
  if (args.Flag("help")) {
    std::fputs(kHelp, stdout);
    return 0;
  }
  std::string truth = args.Require("truth");
  args.RejectUnknown();
  if (args.positionals().size() != 1) {
    std::fputs(kHelp, stderr);
    return 2;
  }
  const std::string map = args.positionals()[0];
  if (std::filesystem::is_directory(truth)) truth += "/truth/objects.json";
  const std::vector<TruthObject> objects = ReadObjectsTruth(truth);
  if (!std::filesystem::exists(map)) throw InputError(map, 0, "MAP", "no such map");
  if (!std::filesystem::is_directory(map) && std::filesystem::path(map).extension() != ".mbtiles")
    throw InputError(map, 0, "MAP", "not a map: expected a .mbtiles file or a map folder");
  std::unique_ptr<TileStore> store = OpenExistingMap(map, /*writable=*/true);
  DetectionBook book(store.get());
  book.Load(*store);
  const TruthReviewResult r = ReviewAgainstTruth(book, objects);
  store->Flush();
  std::printf("reviewed %s against %zu truth objects: %d confirmed, %d rejected, %d marks added, %d kept\n",
              map.c_str(), objects.size(), r.confirmed, r.rejected, r.added, r.kept);
  return 0;
}

}  // namespace seamap::cli
