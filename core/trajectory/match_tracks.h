#pragma once
// Features tracked across frames (refine in 3-D): the inlier matches of the
// registered pairs joined by union-find into tracks, one per seabed point.
// A track that meets one frame twice is inconsistent and dropped. At most
// `max_tracks_per_frame` tracks a frame, longest first: the bundle
// adjustment's size grows with the frames, not with the features. A track
// longer than `max_views` keeps that many views spread evenly over its frames
// (first and last among them): a point seen from 35 frames along a lane and
// across it constrains them nearly as well through 8, and each view kept
// adds to the reduced camera system of the solve.
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

std::vector<MatchTrack> BuildTracks(const std::vector<PairMatches>& pairs, int max_tracks_per_frame,
                                    int max_views = 1 << 30);

}  // namespace seamap
