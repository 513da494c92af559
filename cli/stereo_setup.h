#pragma once
// The stereo options `seamap stereo-locate` and `seamap replay --stereo` both read.
#include <memory>

#include "cli/args.h"
#include "core/stereo/object_georef.h"

namespace seamap {
struct StereoLocateOptions;  // core/controllers/stereo_locate.h, kept out of replay's sight (live_stereo.h)
}  // namespace seamap

namespace seamap::cli {

extern const char* kLiveStereoHelp;

// --rig forward|down and --rig-offset X,Y,Z: the left camera on the vehicle.
RigMount ReadRigMount(Args& args);

// replay's --stereo DIR with the rig and model options stereo-locate takes
// (--calib, --model, --pair-times, --rig, --rig-offset, --method,
// --min-inliers, --max-features); nothing without --stereo, where any of
// them is refused by name. For core/controllers/live_stereo.h's LiveStereo.
std::shared_ptr<const StereoLocateOptions> ReadLiveStereo(Args& args);

}  // namespace seamap::cli
