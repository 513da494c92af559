#include "core/trajectory/pair_candidates.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace seamap {
namespace {

CandidateFrame At(double east, double north, double time_s) {
  CandidateFrame f;
  f.time_s = time_s;
  f.footprint = {cv::Point2d(east - 1, north + 0.75), cv::Point2d(east + 1, north + 0.75),
                 cv::Point2d(east + 1, north - 0.75), cv::Point2d(east - 1, north - 0.75)};
  return f;
}

bool Paired(const std::vector<CandidatePair>& pairs, int i, int j) {
  return std::any_of(pairs.begin(), pairs.end(), [&](const CandidatePair& p) { return p.i == i && p.j == j; });
}

TEST(PairCandidates, CrossPairsWithinTheNavigationsUncertainty) {
  // Two frames a minute apart. 0.4 m of footprint overlap missing... with a
  // relative sigma of 0.2 m they may well overlap: paired. 3 m apart: not.
  CandidateOptions options;
  options.nav_noise_m = 0.005;
  options.drift_m_per_s = 0.2 / 60;  // sigma_rel ~ 0.2 m over a minute
  options.min_overlap = 0.3;
  EXPECT_NEAR(RelativeSigma(options.nav_noise_m, options.drift_m_per_s, 60), 0.2, 0.001);
  {
    const auto pairs = FindCandidatePairs({At(0, 0, 0), At(1.8, 0, 60)}, options);  // 10 % overlap as navigated
    EXPECT_TRUE(Paired(pairs, 0, 1));
    EXPECT_FALSE(pairs.empty() || pairs[0].along_track);
  }
  EXPECT_TRUE(FindCandidatePairs({At(0, 0, 0), At(3.0, 0, 60)}, options).empty());
  // Close in time they are along-track neighbours, not cross pairs.
  const auto line = FindCandidatePairs({At(0, 0, 0), At(0, 0.1, 0.2), At(0, 0.2, 0.4), At(0, 0.3, 0.6)}, options);
  EXPECT_TRUE(Paired(line, 0, 1) && Paired(line, 0, 2) && Paired(line, 1, 3));
  EXPECT_FALSE(Paired(line, 0, 3));
  for (const auto& p : line) EXPECT_TRUE(p.along_track);
}

TEST(PairCandidates, AtMostAFewPartnersAFrameSpreadOverPasses) {
  // One frame, and two later passes over it, each of ten frames.
  std::vector<CandidateFrame> frames{At(0, 0, 0)};
  for (int pass = 1; pass <= 2; ++pass)
    for (int k = 0; k < 10; ++k) frames.push_back(At(0.05 * k, 0.02 * k, 30.0 * pass + 0.2 * k));
  CandidateOptions options;
  options.max_cross_per_frame = 4;
  const auto pairs = FindCandidatePairs(frames, options);
  int partners_of_first = 0, first_pass = 0, second_pass = 0;
  for (const auto& p : pairs) {
    if (p.along_track || p.i != 0) continue;
    ++partners_of_first;
    (p.j <= 10 ? first_pass : second_pass)++;
  }
  EXPECT_LE(partners_of_first, 4);
  EXPECT_GE(first_pass, 1);
  EXPECT_GE(second_pass, 1);
}

TEST(PairCandidates, ALongDriftingSurveyIsSearchedNearEachFrame) {
  // 50 lanes of 100 frames 0.1 m apart, lanes 0.9 m apart: after minutes of
  // 1 m/min drift every footprint may slide over most others, and testing
  // every pair (12.5 million) is what made long surveys quadratic. The grid
  // tests a bounded number per frame and still pairs each lane with the next.
  std::vector<CandidateFrame> frames;
  for (int lane = 0; lane < 50; ++lane)
    for (int k = 0; k < 100; ++k)
      frames.push_back(At(0.9 * lane, lane % 2 == 0 ? 0.1 * k : 9.9 - 0.1 * k, 25.0 * lane + 0.2 * k));
  CandidateOptions options;
  options.nav_noise_m = 0.005;
  options.drift_m_per_s = 1.0 / 60;
  const auto pairs = FindCandidatePairs(frames, options);
  int cross = 0, next_lane = 0;
  for (const auto& p : pairs) {
    if (p.along_track) continue;
    ++cross;
    next_lane += p.j / 100 == p.i / 100 + 1;
  }
  EXPECT_LE(cross, 2 * static_cast<int>(frames.size()));  // at most max_cross_per_frame = 4 partners a frame
  EXPECT_GT(next_lane, 1000);
}

}  // namespace
}  // namespace seamap
