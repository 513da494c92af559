#include "core/trajectory/survey_lines.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "core/util/statistics.h"

namespace seamap {
namespace {

// (-180, 180]
double WrapDeg(double a) {
  a = std::fmod(a, 360.0);
  if (a > 180) a -= 360;
  if (a <= -180) a += 360;
  return a;
}

// Unwrapped along the track, then a running median of 5, narrowed
// symmetrically at the ends so a steady turn keeps its headings.
std::vector<double> SmoothedHeadings(const std::vector<double>& heading_deg) {
  const size_t n = heading_deg.size();
  std::vector<double> unwrapped(n);
  for (size_t i = 0; i < n; ++i)
    unwrapped[i] = i == 0 ? heading_deg[0] : unwrapped[i - 1] + WrapDeg(heading_deg[i] - heading_deg[i - 1]);
  std::vector<double> out(n);
  for (size_t i = 0; i < n; ++i) {
    const size_t half = std::min<size_t>({2, i, n - 1 - i});
    const size_t lo = i - half, hi = i + half + 1;
    out[i] = Median(std::vector<double>(unwrapped.begin() + lo, unwrapped.begin() + hi));
  }
  return out;
}

}  // namespace

std::vector<int> SegmentLines(const std::vector<double>& heading_deg, const std::vector<LocalXY>& position,
                              const LineOptions& options) {
  if (heading_deg.size() != position.size())
    throw std::invalid_argument("SegmentLines: one heading and one position per frame");
  const int n = static_cast<int>(heading_deg.size());
  std::vector<int> line(n, kNoLine);
  if (n == 0) return line;
  const std::vector<double> h = SmoothedHeadings(heading_deg);

  // Seeds: steadiest first; ties in track order.
  std::vector<double> turn(n);
  for (int i = 0; i < n; ++i) turn[i] = std::fabs(h[std::min(i + 1, n - 1)] - h[std::max(i - 1, 0)]);
  std::vector<int> seeds(n);
  std::iota(seeds.begin(), seeds.end(), 0);
  std::stable_sort(seeds.begin(), seeds.end(), [&](int a, int b) { return turn[a] < turn[b]; });

  std::vector<bool> taken(n, false);
  std::vector<std::pair<int, int>> lines;  // [first, last]
  for (int seed : seeds) {
    if (taken[seed]) continue;
    int first = seed, last = seed;
    double lo = 0, hi = 0, sum = 0;  // heading offsets from the seed's
    auto offset = [&](int i) { return h[i] - h[seed]; };
    auto fits = [&](int i) {
      if (i < 0 || i >= n || taken[i]) return false;
      const double o = offset(i);
      return std::max(hi, o) - std::min(lo, o) <= options.max_heading_spread_deg;
    };
    for (;;) {
      const bool left = fits(first - 1), right = fits(last + 1);
      if (!left && !right) break;
      const double mean = sum / (last - first + 1);
      const bool take_left =
          left && (!right || std::fabs(offset(first - 1) - mean) <= std::fabs(offset(last + 1) - mean));
      const int next = take_left ? --first : ++last;
      lo = std::min(lo, offset(next));
      hi = std::max(hi, offset(next));
      sum += offset(next);
    }
    double length_m = 0;
    for (int i = first; i < last; ++i)
      length_m += std::hypot(position[i + 1].east - position[i].east, position[i + 1].north - position[i].north);
    // Turn runs are used up too: a turn is not a seed for anything else.
    for (int i = first; i <= last; ++i) taken[i] = true;
    if (last - first + 1 >= 3 && length_m >= options.min_line_length_m) lines.emplace_back(first, last);
  }
  std::sort(lines.begin(), lines.end());
  for (size_t k = 0; k < lines.size(); ++k)
    for (int i = lines[k].first; i <= lines[k].second; ++i) line[i] = static_cast<int>(k);
  return line;
}

}  // namespace seamap
