// The mixer between a flap unit's network and its wings: the network's outputs (0..1) become
// the two wings' rates, and with headroom, attitude first, as a multirotor's mixer gives roll
// its authority before the collective thrust. ROS-free; no clock.
#pragma once

#include <string>

namespace flapsim {

/// A right and a left wing's rate of one stroke (rad/s).
struct WingRates {
  double right = 0.0;
  double left = 0.0;
};

/// The highest mixer headroom (of the range's span at each end).
constexpr double kMaxMixerHeadroom = 1.0;

/// Empty if `headroom` is in [0, kMaxMixerHeadroom], else why not (naming mixer_headroom).
std::string mixerHeadroomError(double headroom);

/// Two wanted rates mixed into [lo, hi] attitude first: their half-difference d (the roll
/// moment's share) is kept, clamped to half the range's span, and their mean c (the collective:
/// climb or sink) is moved into [lo + |d|, hi - |d|], so the rates are c + d and c - d. A pair
/// already in [lo, hi] comes out as it went in, up to rounding. Needs lo <= hi.
WingRates mixAttitudeFirst(const WingRates& wanted, double lo, double hi);

/// The rates of two outputs `y` (each 0..1, the network's sigmoid) on [lo, hi]. Headroom 0:
/// lo + (hi - lo) y each, as the paper maps them. Headroom h > 0: each onto the range widened
/// by h of its span at both ends, then mixAttitudeFirst into [lo, hi]: a wing that would ask
/// for more than its range keeps the difference that rolls the unit, and the pair gives up
/// collective instead.
WingRates outputRates(const WingRates& y, double lo, double hi, double headroom);

}  // namespace flapsim
