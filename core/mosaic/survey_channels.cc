#include "core/mosaic/survey_channels.h"

#include <algorithm>
#include <set>

#include "core/image/image_read.h"

namespace seamap {
namespace {

// 1 or 3 for the frame at `path`; 0 when it cannot be told.
int ChannelsOf(const std::string& path, int64_t max_pixels) {
  std::string problem;
  const auto header = ReadImageHeader(path, &problem);
  if (!header || TooLargeToDecode(*header, max_pixels)) return 0;
  int channels = header->channels;
  if (channels == 0) {  // a format whose header we do not read
    const cv::Mat m = ReadGuardedImage(path, &problem, max_pixels);
    if (m.empty()) return 0;
    channels = m.channels();
  }
  return channels >= 3 ? 3 : 1;  // gray + alpha is gray
}

}  // namespace

SurveyChannels DecideChannels(const std::vector<FrameSpec>& frames, int64_t max_pixels, int samples) {
  SurveyChannels out;
  const size_t n = frames.size();
  std::set<size_t> picks;
  const size_t want = std::min(n, static_cast<size_t>(std::max(samples, 2)));
  for (size_t i = 0; i < want; ++i) picks.insert(want == 1 ? 0 : i * (n - 1) / (want - 1));
  std::string first_colour, first_gray;
  for (size_t i : picks) {
    const int c = ChannelsOf(frames[i].image_path, max_pixels);
    if (c == 3) {
      ++out.colour;
      if (first_colour.empty()) first_colour = frames[i].image;
    } else if (c == 1) {
      ++out.gray;
      if (first_gray.empty()) first_gray = frames[i].image;
    }
  }
  out.channels = out.colour > 0 && out.colour >= out.gray ? 3 : 1;
  if (out.colour > 0 && out.gray > 0) {
    const bool colour = out.channels == 3;
    out.warning = "the survey mixes gray and colour frames (" + std::to_string(out.gray) + " gray, e.g. " + first_gray +
                  "; " + std::to_string(out.colour) + " colour, e.g. " + first_colour + ", of " +
                  std::to_string(out.gray + out.colour) + " sampled): the map is " +
                  (colour ? "colour; gray frames are painted as colour" : "gray; colour frames are painted as gray");
  }
  return out;
}

}  // namespace seamap
