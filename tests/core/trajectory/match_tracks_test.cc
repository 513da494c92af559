#include "core/trajectory/match_tracks.h"

#include <gtest/gtest.h>

namespace seamap {
namespace {

TEST(MatchTracks, PairMatchesJoinIntoTracksAcrossFrames) {
  // Keypoint 5 of frame 0 = 7 of frame 1 = 2 of frame 2; keypoint 1 of frame 0 = 3 of frame 2.
  const std::vector<PairMatches> pairs = {{0, 1, {{5, 7}}}, {1, 2, {{7, 2}}}, {0, 2, {{1, 3}}}};
  const std::vector<MatchTrack> tracks = BuildTracks(pairs, 10);
  ASSERT_EQ(tracks.size(), 2u);
  const std::vector<std::pair<int, int>> three = {{0, 5}, {1, 7}, {2, 2}}, two = {{0, 1}, {2, 3}};
  EXPECT_TRUE((tracks[0].views == two && tracks[1].views == three) ||
              (tracks[0].views == three && tracks[1].views == two));
}

TEST(MatchTracks, ATrackMeetingAFrameTwiceIsDropped) {
  // 0:1 - 1:1 - 2:1 - 0:2: frame 0 twice, so the matches disagree somewhere.
  const std::vector<PairMatches> pairs = {{0, 1, {{1, 1}}}, {1, 2, {{1, 1}}}, {0, 2, {{2, 1}}}, {0, 1, {{4, 4}}}};
  const std::vector<MatchTrack> tracks = BuildTracks(pairs, 10);
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(tracks[0].views, (std::vector<std::pair<int, int>>{{0, 4}, {1, 4}}));
}

TEST(MatchTracks, AtMostABudgetOfTracksAFrameLongestFirst) {
  // Frames 0 and 1 share 50 two-view tracks; frames 0, 1, 2 one three-view track.
  PairMatches a{0, 1, {}}, b{1, 2, {{100, 100}}};
  for (int k = 0; k < 50; ++k) a.keypoints.emplace_back(k, k);
  a.keypoints.emplace_back(100, 100);
  const std::vector<MatchTrack> tracks = BuildTracks({a, b}, 10);
  ASSERT_EQ(tracks.size(), 10u);
  bool long_one = false;
  for (const auto& t : tracks) long_one |= t.views.size() == 3;
  EXPECT_TRUE(long_one);
}

TEST(MatchTracks, ALongTrackKeepsViewsSpreadOverItsFrames) {
  std::vector<PairMatches> pairs;
  for (int f = 0; f < 20; ++f) pairs.push_back({f, f + 1, {{0, 0}}});  // one point seen by frames 0..20
  const std::vector<MatchTrack> tracks = BuildTracks(pairs, 10, 5);
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(tracks[0].views, (std::vector<std::pair<int, int>>{{0, 0}, {5, 0}, {10, 0}, {15, 0}, {20, 0}}));
}

}  // namespace
}  // namespace seamap
