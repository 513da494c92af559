#pragma once
// How two towed-buoy fits compare where it matters, on the map: whether
// freeing a held parameter moved it beyond chance, and how far the
// candidate fits of one choice spread it (docs/GEOREF.md, "Model choice").
#include <vector>

#include "core/georef/slam_path.h"
#include "core/georef/towed_fit.h"

namespace seamap {

// A parameter is held at its default when it does not show at 3 sigmas,
// yet a current 2.9 sigmas out (0.004 m/s across a transect with a 35 m
// tether) moves the map by 0.7 m, and a reach 0.7 % short on a 45 m
// tether by 0.3 m on alternate legs: the map's lever on them is long. So
// the parameter is freed after all when the map moves between the two fits
// by more than chance would move it (a Hausman test): with the default
// true, the squared displacement averaged over the keyframes has
// expectation freed^2 - held^2 (the difference of the two predictions'
// squares), and its ratio to that is about chi-square with as many degrees
// of freedom as parameters freed, over them; the parameter is freed beyond
// that ratio's 3-sigma level (99.73 %), as the significance tests: 9 for
// one parameter (the reach), 5.9 for two (the current). At 3 times, 4 of 65
// bench surveys without a current or sag freed one and came out worse,
// 0.35 m instead of 0.17 m on a transect; at 5.9 for the reach, a spiral's
// reach pulled 3 % short (by the buoy's unknown start, under GPS noise) was
// freed and put the map 0.8 m off (0.3 m predicted; docs/GEOREF.md,
// "seventh pass").
bool MovedBeyondChance(const SlamPath& path, const TowedFitResult& freed, int freed_parameters,
                       const TowedFitResult& held);

// A candidate fit and its BIC (robust cost in chi-square units + free
// parameters x ln(observations)).
struct WeighedFit {
  const TowedFitResult* fit = nullptr;
  double bic = 0;
};

// Where the candidates' BICs are close they are about equally likely, and
// the map may still differ between them: each keyframe's predicted error
// gets the spread of the candidates' positions about the kept fit's,
// weighted by exp(-dBIC / 2) (the model-averaging variance).
void AddSelectionSpread(const SlamPath& path, const std::vector<WeighedFit>& candidates, TowedFitResult* best);

}  // namespace seamap
