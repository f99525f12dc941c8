#include "dynamics/motor.h"

#include <algorithm>
#include <cmath>

namespace flapsim {

TorqueBounds flatTorqueBounds(double effort) { return TorqueBounds{effort, effort}; }

TorqueBounds motorTorqueBounds(const MotorSpec& motor, double velocity) {
  const double stall = motor.stall_torque;
  const double speed = std::abs(velocity);
  // Driving: along the velocity (either direction at rest).
  double driving = stall;
  if (motor.no_load_speed > 0.0)
    driving = std::min(driving, stall * (1.0 - speed / motor.no_load_speed));
  if (motor.max_power > 0.0 && speed > 0.0) driving = std::min(driving, motor.max_power / speed);
  driving = std::max(driving, 0.0);
  if (velocity > 0.0) return TorqueBounds{driving, stall};
  if (velocity < 0.0) return TorqueBounds{stall, driving};
  return TorqueBounds{driving, driving};
}

double motorWork(double impulse, double step, double displacement) {
  return step > 0.0 ? impulse / step * displacement : 0.0;
}

}  // namespace flapsim
