#include "cli/enhance_setup.h"

namespace seamap::cli {

FeatureEnhanceOptions ReadFeatureEnhance(Args& args) {
  FeatureEnhanceOptions o;
  if (auto v = args.Get("feature-enhance")) o.spec = *v;
  o.Check();
  return o;
}

}  // namespace seamap::cli
