// seamap detections-pack: a map's detections as 24-byte modem records
// (docs/MODEM_RECORD.md), the bytes GET /api/detections.bin gives; and back to CSV.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <stdexcept>

#include "cli/args.h"
#include "cli/commands.h"
#include "core/mission/detection_book.h"
#include "core/mission/mission_classes.h"
#include "core/tiles/modem_record.h"
#include "core/util/error.h"

namespace seamap::cli {
namespace {

const char* kUsage =
    R"(usage: seamap detections-pack MAP [--since SEQ] [--out FILE] [filters]
       seamap detections-pack --decode FILE [--map MAP]
Writes the map's detections changed after SEQ as 24-byte records for an acoustic modem, in seq
order (the bytes of GET /api/detections.bin), to FILE or standard output; prints the last seq
(the next --since) on standard error. --decode prints a file of records as CSV.
  --since SEQ       only detections changed after this change number (default 0: all)
  --class A,B       only these classes          --min-score S   only scores >= S
  --status S,..     unconfirmed, confirmed, rejected            --source S,..  recogniser, operator, stereo
  --bbox W,S,E,N    only inside these bounds    --max K         at most K records (the oldest changes)
  --map MAP         with --decode: class names from this map's class table
)";

// A bad filter names the option as on the command line (the book names the filter's field).
DetectionFilter Filter(Args& args) {
  try {
    return ParseDetectionFilter(args.Get("bbox"), args.Get("class"), args.Get("min-score"), args.GetOr("since", "0"),
                                args.Get("status"), args.Get("source"));
  } catch (const DetectionError& e) {
    throw InputError("", 0, e.field() == "min_score" ? "--min-score" : "--" + e.field(), e.detail());
  }
}

// A record a recogniser stored with inf/NaN numbers is left out and said, not a failed pack.
void WarnUnreadableDetections(const std::string& map, const std::vector<int64_t>& ids) {
  if (ids.empty()) return;
  std::string list;
  for (size_t i = 0; i < ids.size() && i < 10; ++i) list += (i ? ", " : "") + std::to_string(ids[i]);
  std::fprintf(stderr, "warning: %s: %zu detections with non-finite or unreadable numbers left out (ids %s%s)\n",
               map.c_str(), ids.size(), list.c_str(), ids.size() > 10 ? ", ..." : "");
}

int Decode(const std::string& path, const std::optional<std::string>& map) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "--decode", "cannot read the file");
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() % kModemRecordBytes != 0)
    throw InputError(path, 0, "--decode",
                     std::to_string(bytes.size()) + " bytes is not a whole number of 24-byte records");
  std::vector<std::string> classes;
  if (map) classes = MissionClassTable(*OpenExistingMap(*map, false));
  std::printf("%s\n", ModemCsvHeader().c_str());
  for (size_t i = 0; i < bytes.size(); i += kModemRecordBytes) {
    try {
      std::printf("%s\n", ModemCsvLine(DecodeModemRecord(&bytes[i], kModemRecordBytes), classes).c_str());
    } catch (const std::invalid_argument& e) {
      throw InputError(path, 0,
                       "record " + std::to_string(i / kModemRecordBytes + 1) + " (byte " + std::to_string(i) + ")",
                       e.what());
    }
  }
  return 0;
}

}  // namespace

int RunDetectionsPack(int argc, char** argv, int first) {
  Args args(argc, argv, first, {"help"});
  if (args.Flag("help")) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  if (auto decode = args.Get("decode")) {
    auto map = args.Get("map");
    args.RejectUnknown();
    if (!args.positionals().empty())
      throw InputError("", 0, args.positionals()[0], "unexpected argument with --decode; see --help");
    return Decode(*decode, map);
  }
  const DetectionFilter filter = Filter(args);
  size_t max = SIZE_MAX;
  if (auto v = args.Get("max")) {
    const int k = args.GetInt("max", 0);
    if (k < 0) throw InputError("", 0, "--max", "expected a number of records >= 0, got " + *v);
    max = static_cast<size_t>(k);
  }
  const auto out = args.Get("out");
  args.RejectUnknown();
  if (args.positionals().size() != 1)
    throw InputError("", 0, "MAP", "expected one map; see seamap detections-pack --help");
  const std::string path = args.positionals()[0];
  auto store = OpenExistingMap(path, false);
  // The mission's detection book, read-only: the same selection, order and class ids as /api/detections.bin.
  DetectionBook book(nullptr);
  std::vector<int64_t> unreadable;
  book.LoadReadable(*store, &unreadable);
  WarnUnreadableDetections(path, unreadable);
  const PackedDetections packed = book.Pack(filter, max, MissionT0(*store));
  if (out) {
    std::ofstream file(*out, std::ios::binary);
    file.write(reinterpret_cast<const char*>(packed.bytes.data()), static_cast<std::streamsize>(packed.bytes.size()));
    if (!file) throw InputError(*out, 0, "--out", "cannot write the records");
  } else {
    std::fwrite(packed.bytes.data(), 1, packed.bytes.size(), stdout);
  }
  std::fprintf(stderr, "%zu records (%zu bytes), last seq %lld%s%s\n", packed.count, packed.bytes.size(),
               static_cast<long long>(packed.last_seq), out ? " -> " : "", out ? out->c_str() : "");
  return 0;
}

}  // namespace seamap::cli
