#pragma once
// What the buoy's offset along the track may do to a map whose fit held it
// at its default (the straight tether's reach, no lag). On a spiral, or legs
// all flown one way, the fixes barely see that offset (a sagging tether, a
// clock offset: the buoy further behind), and the map moves with it. The
// fit with reach and lag free gives its estimate and standard error; the
// prior says the default is exact with probability exact_share and else
// off by N(0, sigma_m^2) (a spike and a slab: most surveys are as given,
// some are not). docs/GEOREF.md, "Issue 31, eighth pass".

namespace seamap {

struct HeldOffsetPrior {
  double sigma_m = 0;        // the offset where the default is not exact: clock offset and sag together
  double exact_share = 0.5;  // the probability that the default is exact
};

// E[offset^2 | the free fit's estimate offset_m +- sigma_m], in m^2: small
// where the fixes see the offset and show none, the prior's share where
// they see nothing, about offset_m^2 where they show one. 0 where
// prior.sigma_m is 0 (the operator knows reach and clock).
double HeldOffsetMeanSquare(double offset_m, double sigma_m, const HeldOffsetPrior& prior);

}  // namespace seamap
