#pragma once
// Which frame of one track is which frame of another: by image name when the
// two tracks share names, else by time (each truth record takes the nearest
// unused estimate record within a small tolerance). Pairs come in the truth's
// time order (file order when it has no times).
#include <string>
#include <vector>

#include "core/nav/nav_table.h"

namespace seamap {

struct FramePair {
  int estimate = 0;  // index into estimate.records
  int truth = 0;     // index into truth.records
};

struct TrackPairing {
  std::string by;  // "image", "time" or "" when nothing paired
  std::vector<FramePair> pairs;
};

// Time pairing tolerance: a quarter of the truth's median frame interval, at
// most 0.05 s (25 mm at 0.5 m/s): a looser match would add its own error.
double TimePairingTolerance(const NavTable& truth);

// Throws InputError naming the estimate's file, with what was tried, when no frame pairs.
TrackPairing PairFrames(const NavTable& estimate, const NavTable& truth);

}  // namespace seamap
