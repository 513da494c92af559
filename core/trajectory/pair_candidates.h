#pragma once
// Which frames of a survey to register with which (refine): along the track
// each frame with the next two, and across survey lines and loops the frames
// more than `min_gap_s` apart whose footprints, allowed to slide towards
// each other by three sigmas of the navigation's relative uncertainty,
// overlap by at least `min_overlap` of a footprint. At most
// `max_cross_per_frame` such partners a frame, largest overlap first, spread
// over different passes. The slide is capped at `max_slide_m` and each frame
// tests only its `max_tested_per_frame` nearest partners in reach (a grid of
// footprint centres finds them): the search grows linearly with the survey,
// where testing every pair of a long drifting survey grew quadratically.
#include <array>
#include <vector>

#include <opencv2/core.hpp>

namespace seamap {

struct CandidateFrame {
  double time_s = 0;
  std::array<cv::Point2d, 4> footprint;  // ground corners (east, north), from the navigation
  bool usable = true;                    // false: no features, never paired
};

struct CandidateOptions {
  double nav_noise_m = 0.05;        // sigma_n
  double drift_m_per_s = 1.0 / 60;  // rho
  double min_gap_s = 10;
  double min_overlap = 0.3;
  int max_cross_per_frame = 4;
  double max_slide_m = 5;         // cap on the 3-sigma slide: beyond it the navigation predicts no overlap
  int max_tested_per_frame = 48;  // nearest partners in reach whose overlap is computed
};

struct CandidatePair {
  int i = 0, j = 0;  // i < j
  bool along_track = false;
  double overlap = 0;  // predicted share of a footprint
};

// sqrt(2 sigma_n^2 + (rho dt)^2): how far two frames' relative navigation may be off.
double RelativeSigma(double nav_noise_m, double drift_m_per_s, double dt_s);

std::vector<CandidatePair> FindCandidatePairs(const std::vector<CandidateFrame>& frames,
                                              const CandidateOptions& options);

}  // namespace seamap
