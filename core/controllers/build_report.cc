#include "core/controllers/build_report.h"

#include <map>
#include <sstream>

#include "core/util/process_stats.h"

namespace seamap {

std::string BuildSummary(const BuildStats& s) {
  std::map<std::string, int> reasons;
  for (const auto& r : s.rejections) ++reasons[r.reason.substr(0, r.reason.find(':'))];
  std::ostringstream out;
  out << "frames used " << s.frames_used << ", rejected " << s.rejections.size();
  if (!reasons.empty()) {
    out << " (";
    bool first = true;
    for (const auto& [reason, n] : reasons) {
      out << (first ? "" : ", ") << n << " " << reason;
      first = false;
    }
    out << ")";
  }
  int64_t distinct = 0;
  for (const auto& [z, n] : s.tiles_per_zoom) distinct += n;
  out << "; tiles written " << distinct << " (" << s.tiles_written << " writes, " << s.tile_bytes / 1024 << " KiB); "
      << std::fixed;
  out.precision(2);
  out << s.seconds << " s";
  if (s.seconds > 0) {
    out.precision(1);
    out << " (" << s.frames_seen / s.seconds << " frames/s)";
  }
  return out.str();
}

nlohmann::json BuildReportJson(const BuildStats& s, const MosaicPlan& plan, const nlohmann::json& pose_report,
                               size_t in_map) {
  int64_t distinct = 0;
  nlohmann::json per_zoom = nlohmann::json::object();
  for (const auto& [z, n] : s.tiles_per_zoom) {
    distinct += n;
    per_zoom[std::to_string(z)] = n;
  }
  nlohmann::json j = {{"frames_seen", s.frames_seen},
                      {"frames_used", s.frames_used},
                      {"frames_rejected", s.rejections.size()},
                      {"seconds", s.seconds},
                      {"ms_per_frame", s.frames_seen ? 1000 * s.seconds / s.frames_seen : 0},
                      {"frames_per_s", s.seconds > 0 ? s.frames_seen / s.seconds : 0},
                      {"cpu_ms_per_frame", s.frames_seen ? 1000 * s.cpu_seconds / s.frames_seen : 0},
                      {"tiles", distinct},
                      {"tile_writes", s.tiles_written},
                      {"tile_bytes", s.tile_bytes},
                      {"readbacks", s.readbacks},
                      {"frames_in_map", in_map},
                      {"checkpoints", s.checkpoints},
                      {"checkpoint_seconds", s.checkpoint_seconds},
                      {"tiles_per_zoom", per_zoom},
                      {"base_zoom", plan.base_zoom},
                      {"min_zoom", plan.min_zoom},
                      {"peak_rss_bytes", PeakRssBytes()}};
  if (!pose_report.is_null()) j["refine"] = pose_report;
  return j;
}

}  // namespace seamap
