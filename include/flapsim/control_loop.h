// The controller's clock in a simulation stepped by a fixed step, shared by the in-process
// episodes of evolution (flapsim/evolve.h) and the lockstep controller node: a control
// period that is a whole number of simulator steps, and how many periods a duration holds.
// ROS-free; no clock of its own.
#pragma once

#include <cstdint>

namespace flapsim {

class ControlLoop {
 public:
  /// Throws InputError naming both values unless `control_period` is a positive whole
  /// multiple (to 1e-9 of the period) of `step_size` > 0.
  ControlLoop(double control_period, double step_size);

  double period() const { return period_; }
  double stepSize() const { return step_size_; }
  /// Simulator steps per control period (>= 1).
  int stepsPerPeriod() const { return steps_; }
  /// The whole control periods in `duration` (rounded to the nearest); throws InputError if
  /// `duration` is not finite and >= 0 or the count exceeds kMaxPeriods.
  std::int64_t periodsIn(double duration) const;

  /// The most periods one run may hold (about 32 years at 1 ms periods).
  static constexpr std::int64_t kMaxPeriods = std::int64_t{1} << 40;

 private:
  double period_;
  double step_size_;
  int steps_;
};

}  // namespace flapsim
