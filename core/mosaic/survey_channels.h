#pragma once
// Gray or colour: the map's channel count, decided from the survey rather
// than from its first frame. A colour test card or a blank colour frame at
// the start of a gray survey must not turn the whole map into colour tiles
// (nor the other way round): frames spread over the survey are sampled, by
// their headers (image_header.h), and the majority decides.
#include <cstdint>
#include <string>
#include <vector>

#include "core/image/image_header.h"
#include "core/nav/frame_list.h"

namespace seamap {

struct SurveyChannels {
  int channels = 1;          // 1 gray, 3 colour
  int gray = 0, colour = 0;  // sampled frames of each kind (unreadable ones are not counted)
  std::string warning;       // when the sample mixes gray and colour frames
};

// Samples up to `samples` frames evenly over the survey (the first and last
// included); a frame whose header does not say (a palette BMP, a format
// OpenCV alone reads) is decoded, unless over max_pixels. Colour wins a tie.
SurveyChannels DecideChannels(const std::vector<FrameSpec>& frames, int64_t max_pixels, int samples = 64);

}  // namespace seamap
