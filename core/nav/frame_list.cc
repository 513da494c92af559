#include "core/nav/frame_list.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "core/nav/column_aliases.h"
#include "core/nav/csv_table.h"
#include "core/nav/nav_limits.h"
#include "core/nav/nav_series.h"
#include "core/nav/nav_values.h"
#include "core/util/error.h"

namespace seamap {
namespace {

struct ImageTime {
  std::string image;
  double time_s = 0;
  int line = 0;
};

std::string JoinNames(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + Shorten(item);
  return out;
}

// Reads image,time_s rows with the navigation's CSV rules and aliases.
std::vector<ImageTime> ReadImageTimes(const std::string& path, FrameList* out) {
  const CsvTable table = ParseCsv(ReadTextLines(path), path);
  const ColumnMap map = MapColumns(table.header, {}, path, table.header_line);
  for (const char* needed : {"image", "time_s"})
    if (!map.Has(needed))
      throw InputError(path, table.header_line, needed,
                       std::string("image times need a '") + needed + "' column; found: " + JoinNames(table.header) +
                           "; accepted names: " + AcceptedNames(needed));
  const int image_col = map.index.at("image"), time_col = map.index.at("time_s");
  const bool decimal_comma = table.separator != ',';

  std::vector<ImageTime> times;
  std::map<std::string, int> first_line;
  for (const CsvRow& row : table.rows) {
    auto reject = [&](const std::string& field, const std::string& reason) {
      out->rejected.push_back({path, row.line, field, reason});
    };
    if (!row.problem.empty()) {
      reject("", row.problem);
      continue;
    }
    const int needed = std::max(image_col, time_col) + 1;
    if (static_cast<int>(row.fields.size()) < needed) {
      const int missing = static_cast<int>(row.fields.size());
      reject(missing == image_col  ? "image"
             : missing == time_col ? "time_s"
                                   : table.header[missing],
             "line has " + std::to_string(row.fields.size()) + " fields but the header has " +
                 std::to_string(table.header.size()) + "; missing column '" + Shorten(table.header[missing]) + "'");
      continue;
    }
    const std::string image = Trim(row.fields[image_col]);
    if (image.empty()) {
      reject("image", "image is empty");
      continue;
    }
    std::string why;
    const auto time = ParseTimeSeconds(row.fields[time_col], &why, decimal_comma);
    if (!time) {
      reject("time_s", "time_s " + why);
      continue;
    }
    if (std::fabs(*time) > nav_limits::kMaxAbsTimeS) {
      reject("time_s",
             "time_s must be within +-" + FormatNumber(nav_limits::kMaxAbsTimeS) + " s, got " + FormatNumber(*time));
      continue;
    }
    auto [it, inserted] = first_line.emplace(image, row.line);
    if (!inserted) {
      reject("image", "duplicate image '" + image + "' (first at line " + std::to_string(it->second) + ")");
      continue;
    }
    times.push_back({image, *time, row.line});
  }
  return times;
}

std::string ImagePath(const std::string& images_dir, const std::string& image) {
  return (std::filesystem::path(images_dir) / image).string();
}

void OrderAndIndex(std::vector<FrameSpec>& frames) {
  const bool all_timed =
      std::all_of(frames.begin(), frames.end(), [](const FrameSpec& f) { return f.time_s.has_value(); });
  if (all_timed)
    std::stable_sort(frames.begin(), frames.end(),
                     [](const FrameSpec& a, const FrameSpec& b) { return *a.time_s < *b.time_s; });
  for (size_t i = 0; i < frames.size(); ++i) frames[i].index = static_cast<int>(i);
}

}  // namespace

FrameList MatchFrames(const NavTable& nav, const std::string& images_dir,
                      const std::optional<std::string>& image_times_csv) {
  FrameList out;
  if (nav.has_images) {
    if (image_times_csv)
      out.warnings.push_back(*image_times_csv + ": image times ignored: " + nav.source + " names the images");
    std::map<std::string, int> first_line;
    for (const NavRecord& record : nav.records) {
      if (record.image.empty()) continue;  // a navigation sample between photos
      auto [it, inserted] = first_line.emplace(record.image, record.line);
      if (!inserted) {
        out.rejected.push_back(
            {nav.source, record.line, "image",
             "duplicate image '" + record.image + "' (first at line " + std::to_string(it->second) + ")"});
        continue;
      }
      FrameSpec frame;
      frame.image = record.image;
      frame.image_path = ImagePath(images_dir, record.image);
      frame.time_s = record.time_s;
      frame.pose = record.pose;
      frame.nav_line = record.line;
      out.frames.push_back(std::move(frame));
    }
    OrderAndIndex(out.frames);
    return out;
  }
  if (!nav.has_times || !image_times_csv)
    throw InputError(nav.source, 0, "image",
                     "navigation has no image column; give image times with --image-times FILE");

  const NavSeries series(nav.records);
  for (const ImageTime& shot : ReadImageTimes(*image_times_csv, &out)) {
    auto pose = series.PoseAt(shot.time_s);
    if (!pose) {
      out.rejected.push_back({*image_times_csv, shot.line, "time_s",
                              "time_s " + FormatNumber(shot.time_s) + " is outside the navigation's time span " +
                                  series.SpanText() + " in " + nav.source});
      continue;
    }
    FrameSpec frame;
    frame.image = shot.image;
    frame.image_path = ImagePath(images_dir, shot.image);
    frame.time_s = shot.time_s;
    frame.pose = *pose;
    out.frames.push_back(std::move(frame));
  }
  // Read problems and out-of-span times, back in file order.
  std::stable_sort(out.rejected.begin(), out.rejected.end(),
                   [](const Rejection& a, const Rejection& b) { return a.line < b.line; });
  OrderAndIndex(out.frames);
  return out;
}

}  // namespace seamap
