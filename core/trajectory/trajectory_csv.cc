#include "core/trajectory/trajectory_csv.h"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "core/util/error.h"

namespace seamap {
namespace {

const char* kHeader = "image,time_s,lat,lon,x_m,y_m,depth_m,altitude_m,heading_deg,pitch_deg,roll_deg";

// CSV quoting where needed (the reader understands "a, b" and "" escapes), so
// an odd image name cannot shift the columns.
std::string Quoted(const std::string& text, const std::string& path, int line, const char* field) {
  if (text.find_first_of("\r\n") != std::string::npos)
    throw InputError(path, line, field, std::string(field) + " contains a line break");
  const bool plain = text.find_first_of(",;\t\"") == std::string::npos &&
                     (text.empty() || (text.front() != ' ' && text.back() != ' '));
  if (plain) return text;
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string Number(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

}  // namespace

void WriteTrajectoryCsv(const std::string& path, const std::vector<TrajectoryRow>& rows, const LocalFrame& frame) {
  const bool with_flags =
      std::any_of(rows.begin(), rows.end(), [](const TrajectoryRow& r) { return !r.flags.empty(); });
  std::string text = std::string(kHeader) + (with_flags ? ",flags\n" : "\n");
  int line = 1;
  for (const TrajectoryRow& row : rows) {
    ++line;
    if (row.image.empty() && !row.time_s)
      throw InputError(path, line, "image", "trajectory row has neither an image nor a time_s");
    const VehiclePose& p = row.pose;
    const LatLon ll = frame.ToLatLon({p.east_m, p.north_m});
    text += Quoted(row.image, path, line, "image") + ",";
    text += (row.time_s ? Number("%.6f", *row.time_s) : "") + ",";
    // 1e-10 degrees of latitude is 0.011 mm; positions to 1 um; angles to 1e-7 degrees.
    text += Number("%.10f", ll.lat) + "," + Number("%.10f", ll.lon) + ",";
    text += Number("%.6f", p.east_m) + "," + Number("%.6f", p.north_m) + ",";
    text += Number("%.6f", p.depth_m) + "," + Number("%.6f", p.altitude_m) + ",";
    text += Number("%.7f", p.heading_deg) + "," + Number("%.7f", p.pitch_deg) + "," + Number("%.7f", p.roll_deg);
    if (with_flags) text += "," + Quoted(row.flags, path, line, "flags");
    text += "\n";
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw InputError(path, 0, "", "cannot write the trajectory file");
  out << text;
  out.close();
  if (!out) throw InputError(path, 0, "", "cannot write the trajectory file (disk full?)");
}

}  // namespace seamap
