// StepData: what a creature's last step did, written stage by stage (the stages of
// src/core/world/creature_step.h), after MuJoCo's mjData: named outputs of the step, read
// through World::stepData. ROS-free.
#pragma once

#include <vector>

#include "flapsim/air_model.h"
#include "flapsim/types.h"

namespace flapsim {

/// The outputs of a creature's last step. A step cut into substeps (WorldParams::turn_substep)
/// gives each output's mean over the step: the impulses of its substeps over the step's length,
/// their moments taken about the COMs of the step's start. All zero, with `step` 0, before the
/// first step after a spawn, reset or World::setState, and after a step the watchdog refused
/// (a frozen creature is driven by nothing).
struct StepData {
  double step = 0.0;     ///< s: the step's length (WorldParams::step_size), 0 if none
  int substeps = 0;      ///< the (sub)steps it was taken in
  bool contact = false;  ///< the creature touched the ground in it

  /// Per model link, world frame: its centre of mass at the step's start (index = model link).
  std::vector<Vec3> com;
  /// Per model link: the air's wrench about `com` (world frame) over the step: the fluid law's
  /// wrench summed over the link's cells, buoyancy, and the implicit drag's share that the
  /// servo stage's solve actually applied (its impulse over the step's length). Zero for a
  /// link without an aero surface, and without air. The added mass is not in it: the fluid the
  /// plates carry counts as part of the creature (its momentum and its velocity products are
  /// the creature's), so that the sum over the links of these wrenches, gravity and
  /// `external_wrench` is what changes the momentum of the creature and the fluid it carries
  /// in a step without contact (the momentum balance, dynamics/momentum_balance.h).
  std::vector<Wrench> fluid_wrench;
  /// Per model link: the external wrenches (World::applyWrench) about `com`, world frame.
  std::vector<Wrench> external_wrench;

  /// Per model joint: the torque (force, if prismatic) its servo applied: the servo's impulse
  /// over the step's length (wing motor, velocity target, feathering or Coulomb friction; not
  /// damping or springs; 0 for fixed joints and joints without a servo at work).
  std::vector<double> servo_effort;
  /// Per model joint: its motor's mean power over the step (World::power's `power`: the
  /// servo's impulse times the mean of the joint's start and end velocities, per (sub)step,
  /// over the step's length; 0 for joints without a motor).
  std::vector<double> joint_power;
  double total_power = 0.0;  ///< W: the sum of joint_power
};

}  // namespace flapsim
