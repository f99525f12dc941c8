// Joint motors: what torque a joint's motor can give at a joint velocity, and the mechanical
// work it does. Pure functions, no state. Private to flapsim_core.
//
// A motor without a <motor> annotation is today's flat effort limit: |torque| <= effort at any
// speed. With one (flapsim::MotorSpec) it is a DC motor behind a current-limited driver:
//   - driving (torque along the velocity v): at most the torque-speed line
//     stall_torque (1 - |v| / no_load_speed), and at most max_power / |v|;
//   - braking (torque against v): at most stall_torque (the driver's current limit; a DC
//     motor braking against its supply could give more, stall_torque (1 + |v| / no_load_speed),
//     but not through a driver that limits its current to the stall current);
//   - neither bound below zero: beyond its no-load speed the motor freewheels (it is not
//     forced to brake).
// The bounds are taken at the velocity at the start of a (sub)step: explicit in the velocity,
// like the rest of a step's forces.
#pragma once

#include "flapsim/creature_model.h"

namespace flapsim {

/// Bounds on a motor's torque (force, if prismatic) in the joint's positive and negative
/// directions: -negative <= torque <= positive, both >= 0.
struct TorqueBounds {
  double positive = 0.0;
  double negative = 0.0;
};

/// The flat limit: |torque| <= effort.
TorqueBounds flatTorqueBounds(double effort);

/// A DC motor's bounds at joint velocity `velocity` (see the file comment).
TorqueBounds motorTorqueBounds(const MotorSpec& motor, double velocity);

/// Mechanical work of a motor over a step: torque (impulse / step) times the joint's
/// displacement in the step (J). Positive: the motor drives the joint; negative: it brakes it.
double motorWork(double impulse, double step, double displacement);

/// A joint's energy counters: net work and the sum of the steps' positive work (J). The
/// positive work is what a motor that cannot recover the braking energy draws (at 100 %
/// efficiency); the net work is what one that recovers all of it draws.
struct JointEnergy {
  double work = 0.0;
  double positive_work = 0.0;
  void add(double step_work) {
    work += step_work;
    if (step_work > 0.0) positive_work += step_work;
  }
};

}  // namespace flapsim
