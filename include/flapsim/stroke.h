// The flapping stroke: a wing-rate command turned into a joint-velocity target.
#pragma once

#include <string>

namespace flapsim {

/// Downstroke rate w1 and upstroke rate w2 (rad/s, >= 0), amplitude theta0 (rad, >= 0).
struct StrokeCommand {
  double downstroke_rate = 0.0;
  double upstroke_rate = 0.0;
  double amplitude = 0.0;
  /// Feathering: pitch (rad, |.| <= pi/2) of the wing about its span during the upstroke,
  /// for wings with a feather joint; 0 keeps the wing flat.
  double feather = 0.0;
};

/// Largest stroke rate (rad/s) and amplitude (rad) a command may give.
constexpr double kMaxStrokeRate = 1e5;
constexpr double kMaxStrokeAmplitude = 1e3;

/// Empty string if valid, else a message naming the bad field.
std::string validateStroke(const StrokeCommand& command);

/// Swings down at w1 to -theta0, then up at w2 to +theta0, and repeats.
/// Starts with a downstroke. Pure state machine: no clock, no physics.
class StrokeGenerator {
 public:
  enum class Phase { kDown, kUp };

  void setCommand(const StrokeCommand& command) { command_ = command; }
  const StrokeCommand& command() const { return command_; }
  Phase phase() const { return phase_; }
  void reset() { phase_ = Phase::kDown; }

  /// Joint-velocity target for the current joint angle (updates the phase). With a step
  /// `dt` > 0 it is the mean velocity over the next step of the ideal stroke from this
  /// angle: a step in which the stroke would reach its turning point goes there and back
  /// for the rest of the step, so the turn falls where the command says whatever the step
  /// size (without it, a wing overshoots by up to one step's travel, w dt).
  double target(double joint_position, double dt = 0.0);
  /// Time until the stroke reaches its next turning point from this angle at the current
  /// phase's rate (0 if it is there or past it; infinity at rate 0). Changes nothing.
  double timeToTurn(double joint_position) const;

 private:
  StrokeCommand command_;
  Phase phase_ = Phase::kDown;
};

}  // namespace flapsim
