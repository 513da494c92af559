#pragma once
// What a navigation value may be: finite, and physically plausible for a
// vehicle photographing the seabed. The limits are generous on purpose: they
// catch corrupted and mistyped values (1e308, an altitude in millimetres),
// not unusual surveys; a value past them would make the build place a frame
// nowhere sensible or paint without bound. A line with such a value is
// skipped and reported with file, line and field. Listed in data/README.md.
namespace seamap::nav_limits {

// |x_m|, |y_m|, and geographic positions' distance from the origin: the
// local transverse Mercator frame is not meant for more.
constexpr double kMaxLocalM = 3.0e6;
// 0 < altitude_m <= this: above the seabed.
constexpr double kMaxAltitudeM = 1000;
// depth_m in [kMinDepthM, kMaxDepthM]: below the surface (deeper than the
// Challenger Deep's 10,935 m is a typo; negative is above the surface).
constexpr double kMinDepthM = -1000;
constexpr double kMaxDepthM = 12000;
// |pitch_deg|, |roll_deg| < this (heading is any finite value, normalised).
constexpr double kMaxAttitudeDeg = 90;
// |time_s| <= this: any epoch, even milliseconds since 1970 read as seconds,
// and differences of two times never overflow.
constexpr double kMaxAbsTimeS = 1e13;

}  // namespace seamap::nav_limits
