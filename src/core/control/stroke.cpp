#include "flapsim/stroke.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace flapsim {

StrokeShape strokeShapeFromString(const std::string& text) {
  if (text == "triangle") return StrokeShape::kTriangle;
  if (text == "sine") return StrokeShape::kSine;
  throw std::invalid_argument("stroke shape must be triangle or sine, got '" + text + "'");
}

std::string toString(StrokeShape shape) {
  return shape == StrokeShape::kSine ? "sine" : "triangle";
}

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
  if (!std::isfinite(c.downstroke_feather) || std::abs(c.downstroke_feather) > M_PI / 2) {
    return "downstroke feather angle must be finite and within +-pi/2";
  }
  if (!std::isfinite(c.offset) || std::abs(c.offset) > kMaxStrokeAmplitude) {
    return "offset must be finite and within +-1000 rad";
  }
  if (c.shape != StrokeShape::kTriangle && c.shape != StrokeShape::kSine) {
    return "shape must be triangle or sine";
  }
  return "";
}

void StrokeGenerator::setCommand(const StrokeCommand& command) {
  if (command.shape != command_.shape) started_ = false;
  command_ = command;
}

double StrokeGenerator::halfPeriod(Phase phase) const {
  const double rate = phase == Phase::kDown ? command_.downstroke_rate : command_.upstroke_rate;
  return rate > 0.0 ? 2.0 * command_.amplitude / rate : std::numeric_limits<double>::infinity();
}

namespace {

// The share of a half-stroke's travel done at `progress` through it along a half cosine: 0 at
// the start, 1 at the end, at rest at both.
double halfCosine(double progress) { return 0.5 - 0.5 * std::cos(M_PI * progress); }

}  // namespace

double StrokeGenerator::turningPoint(Phase phase) const {
  return command_.offset + (phase == Phase::kDown ? -command_.amplitude : command_.amplitude);
}

double StrokeGenerator::sineTarget(double q, double dt) {
  if (!started_) {
    // From where the wing is to this half-stroke's turning point.
    progress_ = 0.0;
    from_ = q;
    to_ = turningPoint(phase_);
    started_ = true;
  }
  // The stroke's clock runs `dt` on; at each turn the next half-stroke starts where this one
  // ends and goes to the command's turning point then (several turns in one step only at
  // absurd rates; bounded for safety).
  double left = dt;
  for (int turns = 0; left > 0.0 && turns < 64; ++turns) {
    const double half = halfPeriod(phase_);
    if (!(half > 0.0) || !std::isfinite(half)) break;  // rate or amplitude 0: the stroke stands
    const double to_end = (1.0 - progress_) * half;
    if (to_end > left) {
      progress_ += left / half;
      break;
    }
    left -= to_end;
    progress_ = 0.0;
    phase_ = phase_ == Phase::kDown ? Phase::kUp : Phase::kDown;
    from_ = to_;
    to_ = turningPoint(phase_);
  }
  const double angle = from_ + (to_ - from_) * halfCosine(progress_);
  if (dt > 0.0) return (angle - q) / dt;
  const double half = halfPeriod(phase_);
  if (!(half > 0.0) || !std::isfinite(half)) return 0.0;
  return (to_ - from_) * 0.5 * M_PI / half * std::sin(M_PI * progress_);
}

double StrokeGenerator::target(double q, double dt) {
  if (command_.shape == StrokeShape::kSine) return sineTarget(q, dt);
  const double a = command_.amplitude;
  const double w1 = command_.downstroke_rate, w2 = command_.upstroke_rate;
  q -= command_.offset;
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
  if (command_.shape == StrokeShape::kSine) {
    const double half = halfPeriod(phase_);
    if (!(half > 0.0) || !std::isfinite(half)) return std::numeric_limits<double>::infinity();
    return (1.0 - (started_ ? progress_ : 0.0)) * half;
  }
  q -= command_.offset;
  const double rate = down ? command_.downstroke_rate : command_.upstroke_rate;
  const double distance = std::max(0.0, down ? q + a : a - q);
  if (rate <= 0.0) return distance > 0.0 ? std::numeric_limits<double>::infinity() : 0.0;
  return distance / rate;
}

double StrokeGenerator::featherTarget() const {
  const bool down = phase_ == Phase::kDown;
  const double own = down ? command_.downstroke_feather : command_.feather;
  if (command_.shape != StrokeShape::kSine || !started_) return own;
  const double other = down ? command_.feather : command_.downstroke_feather;
  // Distance to the nearer turn, in half-strokes.
  const double x = std::min(progress_, 1.0 - progress_);
  if (x >= kSineFlipFraction) return own;
  const double s = 0.5 + 0.5 * std::sin(0.5 * M_PI * x / kSineFlipFraction);
  return other + (own - other) * s;
}

}  // namespace flapsim
