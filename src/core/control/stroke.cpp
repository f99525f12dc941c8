#include "flapsim/stroke.h"

#include <algorithm>
#include <cmath>
#include <limits>

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
  if (c.downstroke_rate > kMaxStrokeRate || c.upstroke_rate > kMaxStrokeRate) {
    return "stroke rates must be at most 1e5 rad/s";
  }
  if (c.amplitude > kMaxStrokeAmplitude) return "amplitude must be at most 1000 rad";
  if (!std::isfinite(c.feather) || std::abs(c.feather) > M_PI / 2) {
    return "feather angle must be finite and within +-pi/2";
  }
  return "";
}

double StrokeGenerator::target(double q, double dt) {
  const double a = command_.amplitude;
  const double w1 = command_.downstroke_rate, w2 = command_.upstroke_rate;
  if (phase_ == Phase::kDown && q <= -a) {
    phase_ = Phase::kUp;
  } else if (phase_ == Phase::kUp && q >= a) {
    phase_ = Phase::kDown;
  }
  if (dt > 0.0) {
    // Time to the turning point at the current rate, then back at the other rate.
    if (phase_ == Phase::kDown && w1 > 0.0 && q - w1 * dt < -a) {
      const double to_turn = (q + a) / w1;
      phase_ = Phase::kUp;
      return (-a - q + w2 * (dt - to_turn)) / dt;
    }
    if (phase_ == Phase::kUp && w2 > 0.0 && q + w2 * dt > a) {
      const double to_turn = (a - q) / w2;
      phase_ = Phase::kDown;
      return (a - q - w1 * (dt - to_turn)) / dt;
    }
  }
  return phase_ == Phase::kDown ? -w1 : w2;
}

double StrokeGenerator::timeToTurn(double q) const {
  const double a = command_.amplitude;
  const bool down = phase_ == Phase::kDown;
  const double rate = down ? command_.downstroke_rate : command_.upstroke_rate;
  const double distance = std::max(0.0, down ? q + a : a - q);
  if (rate <= 0.0) return distance > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
  return distance / rate;
}

}  // namespace flapsim
