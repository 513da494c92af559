#pragma once
// Survey lines of a track: which frames were taken on the same straight pass,
// so that frames of different passes can be compared (cross-pass errors).
//
// A line is a run of consecutive frames whose headings all lie within
// `max_heading_spread_deg` (20) of each other. Runs are grown from the
// steadiest frames first (smallest heading change between their neighbours),
// one frame at a time on the side whose heading is closer to the run's mean,
// so a line takes the straight part and stops symmetrically where the turns
// begin, instead of a left-to-right sweep letting the end of a turn eat the
// spread and cut the pass in two. Runs shorter than `min_line_length_m` of
// path (or 3 frames) are turns: their frames belong to no line. Headings are
// first median-filtered over 5 frames (on the unwrapped angle) so one or two
// wild headings cannot split a pass. A pass that curves slowly by more than
// the spread becomes several lines.
#include <vector>

#include "core/geo/local_frame.h"

namespace seamap {

struct LineOptions {
  double max_heading_spread_deg = 20;
  double min_line_length_m = 1.0;
};

constexpr int kNoLine = -1;

// heading_deg and position: one per frame, in track (time) order, same size.
// Returns a line number per frame (0, 1, ... in order of the lines' first
// frames) or kNoLine for turn frames.
std::vector<int> SegmentLines(const std::vector<double>& heading_deg, const std::vector<LocalXY>& position,
                              const LineOptions& options = {});

}  // namespace seamap
