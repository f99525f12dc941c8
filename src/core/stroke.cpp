#include "flapsim/stroke.h"

#include <cmath>

namespace flapsim {

std::string validateStroke(const StrokeCommand& c) {
  if (!std::isfinite(c.downstroke_rate) || c.downstroke_rate < 0.0) {
    return "downstroke rate must be finite and >= 0";
  }
  if (!std::isfinite(c.upstroke_rate) || c.upstroke_rate < 0.0) {
    return "upstroke rate must be finite and >= 0";
  }
  if (!std::isfinite(c.amplitude) || c.amplitude < 0.0) {
    return "amplitude must be finite and >= 0";
  }
  if (!std::isfinite(c.feather) || std::abs(c.feather) > M_PI / 2) {
    return "feather angle must be finite and within +-pi/2";
  }
  return "";
}

double StrokeGenerator::target(double q) {
  if (phase_ == Phase::kDown && q <= -command_.amplitude) {
    phase_ = Phase::kUp;
  } else if (phase_ == Phase::kUp && q >= command_.amplitude) {
    phase_ = Phase::kDown;
  }
  return phase_ == Phase::kDown ? -command_.downstroke_rate : command_.upstroke_rate;
}

}  // namespace flapsim
