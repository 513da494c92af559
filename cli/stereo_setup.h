#pragma once
// Command-line pieces the stereo commands share.
#include "cli/args.h"
#include "core/stereo/object_georef.h"

namespace seamap::cli {

// --rig forward|down and --rig-offset X,Y,Z: the stereo rig on the vehicle.
RigMount ReadRigMount(Args& args);

}  // namespace seamap::cli
