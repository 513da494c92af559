#pragma once
// Features tracked across frames (refine in 3-D): the inlier matches of the
// registered pairs joined by union-find into tracks, one per seabed point.
// A track that meets one frame twice is inconsistent and dropped. At most
// `max_tracks_per_frame` tracks a frame, longest first: the bundle
// adjustment's size grows with the frames, not with the features.
#include <utility>
#include <vector>

namespace seamap {

struct PairMatches {
  int i = 0, j = 0;                            // frames
  std::vector<std::pair<int, int>> keypoints;  // (keypoint of i, keypoint of j)
};

struct MatchTrack {
  std::vector<std::pair<int, int>> views;  // (frame, keypoint), by frame
};

std::vector<MatchTrack> BuildTracks(const std::vector<PairMatches>& pairs, int max_tracks_per_frame);

}  // namespace seamap
