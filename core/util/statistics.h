#pragma once
// The order statistics the code base shares: one median, one percentile.
#include <vector>

namespace seamap {

// The upper median: element n/2 of the values in ascending order (for an
// even count the larger of the middle pair, so the result is always one of
// the values); 0 when `values` is empty. The mosaic plan's zoom and latitude
// come from it, so maps depend on this convention.
double Median(std::vector<double> values);

// The p-quantile (p in [0, 1], clamped) by linear interpolation between the
// order statistics at rank p * (n - 1) (Hyndman & Fan type 7, numpy's
// default): p = 0 is the smallest value, p = 1 the largest, and p = 0.5 the
// classical median (the mean of the middle pair for an even count, unlike
// Median above). 0 when `values` is empty.
double Percentile(std::vector<double> values, double p);

}  // namespace seamap
