#include "flapsim/output_mixer.h"

#include <algorithm>
#include <cmath>

namespace flapsim {

std::string mixerHeadroomError(double headroom) {
  if (headroom >= 0.0 && headroom <= kMaxMixerHeadroom) return "";
  return "mixer_headroom must be in [0, 1] (of the rate range's span)";
}

WingRates mixAttitudeFirst(const WingRates& wanted, double lo, double hi) {
  const double half_span = 0.5 * (hi - lo);
  const double d = std::clamp(0.5 * (wanted.right - wanted.left), -half_span, half_span);
  const double c =
      std::clamp(0.5 * (wanted.right + wanted.left), lo + std::abs(d), hi - std::abs(d));
  return WingRates{c + d, c - d};
}

WingRates outputRates(const WingRates& y, double lo, double hi, double headroom) {
  // At headroom 0 the widened map is the paper's to the bit (lo - 0, 1 x span), and it is not
  // mixed: (c + d) need not give back the bit it came from.
  const double span = hi - lo;
  const double wide_lo = lo - headroom * span, wide_span = (1.0 + 2.0 * headroom) * span;
  const WingRates wanted{wide_lo + wide_span * y.right, wide_lo + wide_span * y.left};
  return headroom == 0.0 ? wanted : mixAttitudeFirst(wanted, lo, hi);
}

}  // namespace flapsim
