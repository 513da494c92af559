#include "core/trajectory/match_tracks.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <unordered_map>

namespace seamap {
namespace {

class UnionFind {
 public:
  int Add() {
    parent_.push_back(static_cast<int>(parent_.size()));
    return parent_.back();
  }
  int Find(int a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];
    return a;
  }
  void Join(int a, int b) {
    a = Find(a);
    b = Find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

}  // namespace

std::vector<MatchTrack> BuildTracks(const std::vector<PairMatches>& pairs, int max_tracks_per_frame, int max_views) {
  UnionFind sets;
  std::unordered_map<uint64_t, int> node_of;  // (frame, keypoint) -> node
  std::vector<std::pair<int, int>> view_of;   // node -> (frame, keypoint)
  auto node = [&](int frame, int keypoint) {
    const uint64_t key = (static_cast<uint64_t>(static_cast<uint32_t>(frame)) << 32) | static_cast<uint32_t>(keypoint);
    const auto it = node_of.find(key);
    if (it != node_of.end()) return it->second;
    const int id = sets.Add();
    node_of.emplace(key, id);
    view_of.emplace_back(frame, keypoint);
    return id;
  };
  for (const PairMatches& p : pairs)
    for (const auto& m : p.keypoints) sets.Join(node(p.i, m.first), node(p.j, m.second));

  std::unordered_map<int, int> track_of_root;
  std::vector<MatchTrack> tracks;
  for (int id = 0; id < static_cast<int>(view_of.size()); ++id) {
    const int root = sets.Find(id);
    auto it = track_of_root.find(root);
    if (it == track_of_root.end()) {
      it = track_of_root.emplace(root, static_cast<int>(tracks.size())).first;
      tracks.emplace_back();
    }
    tracks[it->second].views.push_back(view_of[id]);
  }
  std::vector<MatchTrack> consistent;
  for (MatchTrack& t : tracks) {
    std::sort(t.views.begin(), t.views.end());
    bool twice = false;
    for (size_t k = 1; k < t.views.size(); ++k) twice |= t.views[k].first == t.views[k - 1].first;
    if (twice || t.views.size() < 2) continue;
    const int n = static_cast<int>(t.views.size()), keep = std::max(2, max_views);
    if (n > keep) {
      std::vector<std::pair<int, int>> spread;
      for (int m = 0; m < keep; ++m)
        spread.push_back(t.views[static_cast<size_t>(std::lround(m * (n - 1.0) / (keep - 1)))]);
      t.views = std::move(spread);
    }
    consistent.push_back(std::move(t));
  }
  // Longest first (ties: by first view, for a deterministic result).
  std::vector<int> order(consistent.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    if (consistent[a].views.size() != consistent[b].views.size())
      return consistent[a].views.size() > consistent[b].views.size();
    return consistent[a].views.front() < consistent[b].views.front();
  });
  std::unordered_map<int, int> per_frame;
  std::vector<MatchTrack> out;
  for (int k : order) {
    const MatchTrack& t = consistent[k];
    bool wanted = false;
    for (const auto& v : t.views) wanted |= per_frame[v.first] < max_tracks_per_frame;
    if (!wanted) continue;
    for (const auto& v : t.views) ++per_frame[v.first];
    out.push_back(t);
  }
  // In order of first view: the bundle's points come out in a stable order.
  std::sort(out.begin(), out.end(), [](const MatchTrack& a, const MatchTrack& b) { return a.views < b.views; });
  return out;
}

}  // namespace seamap
