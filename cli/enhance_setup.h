#pragma once
// --feature-enhance, as every command with a feature front end reads it
// (trajectory, build --refine-nav, stereo-model, stereo-locate, stereo-points).
#include "cli/args.h"
#include "core/enhance/chain_choice.h"

namespace seamap::cli {

// --feature-enhance off|auto|LIST (default off); InputError naming it.
FeatureEnhanceOptions ReadFeatureEnhance(Args& args);

}  // namespace seamap::cli
