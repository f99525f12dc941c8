// A creature's step as named stages, after MuJoCo's mj_step, in the order the code runs them
// (creature_step.cpp: stepCreature, stepInSteadyAir, subStep). Each stage writes its named
// outputs of the step into the creature's step data (world/step_record.h; read through
// World::stepData, flapsim/step_data.h). One step of `step_size`:
//
//   check       a creature the watchdog froze is not stepped; the state before the step is
//               kept (stepCreature)
//   air         the air's velocity at the root's COM (wind, gust, turbulence), uniform over
//               the creature for the step (creatureAirVelocity)
//   substeps    a step in which a wing reverses is cut at the turn into pieces of at most
//               turn_substep (world/joint_drives.h: strokeTurn); each (sub)step runs:
//     position      the link frames of the (sub)step's start: those the last one ended with
//                   (dynamics/bullet_body.h: LinkFrames), and the momentum and velocities
//                   then (dynamics/momentum_balance.h, dynamics/servo_stage.h: begin)
//     actuation     joint drives -> servo demands and passive torques (world/joint_drives.h)
//     fluid         the air's wrenches and this step's implicit fluid (world/fluid_stage.h)
//                   -> the step data's fluid_wrench
//     external      the user's external wrenches (this file) -> external_wrench
//     velocities    Bullet's unconstrained velocities under gravity and the forces (its
//                   articulated-body pass, or dynamics/tree_dynamics.h on a lean step):
//                   dynamics/bullet_scene.h: ServoWorld::beginStep
//     servos        the servo stage solves servos and the implicit fluid together and adds
//                   the velocity change they cause (dynamics/servo_stage.h: solve) ->
//                   servo_effort, fluid_wrench (the implicit drag's share)
//     constraints   contacts and joint limits: Bullet's constraint solve (on a lean step
//                   only if a limit may act, dynamics/joint_limit.h): ServoWorld::constrain
//                   -> contact
//     positions     Bullet's integration of the positions: ServoWorld::integrate
//     saturated     saturated servos move by the trapezoid of their velocities
//                   (dynamics/servo_stage.h: integrateSaturated)
//     momentum      the rigid correction that keeps the momentum that of the external
//                   impulses, and the frames of the (sub)step's end (momentum_balance.h: end)
//     power         each motor's work over the (sub)step (world/power.h)
//     energy        the air's and the damping's work, while the energy audit is on
//                   (world/energy_meter.h)
//   wrenches    the external wrenches count down their steps
//   watchdog    a non-finite or too fast result is refused: the creature is put back as it
//               was and frozen, its step data cleared (dynamics/bullet_body.h: motionFault);
//               else the step's power closes the step data -> joint_power, total_power
//
// Private to flapsim_core.
#pragma once

#include <cstdint>

#include "flapsim/world.h"
#include "world/creature.h"
#include "world/fluid_stage.h"

namespace flapsim {

// What every creature's step reads of its world.
struct StepContext {
  const WorldParams& params;
  const AirStage& air;
  bool energy_audit = false;  // the energy meter counts (World::setEnergyAudit)
  double time = 0.0;          // s, the step's start
};

// The air's velocity at the creature's root COM at `time`: the steady wind, the gust and the
// creature's realisation of the turbulence (World::airVelocity).
Vec3 creatureAirVelocity(const CreatureSim& sim, const AirParams& air, double time);

// `w` on model link `link` as the external stage applies it: its point in the link's COM frame
// as the link is now (`kin`), its duration in whole steps of `step_size` (as
// gazebo_msgs/ApplyBodyWrench: shorter than a step, 0 included, is one step), its start time.
ActiveWrench activeWrench(const ExternalWrench& w, int link, const BodyKinematics& kin,
                          double step_size);

// Whether a step starting at `step_start` (s) starts a wrench waiting for `start_time`: at
// or after it, within kWrenchStartTolerance (decided per step, never per substep).
inline bool startsWrench(double step_start, double start_time) {
  return step_start >= start_time - kWrenchStartTolerance;
}

// The number of the first step, from `next` on, that starts a wrench of `start_time` when
// step k starts at k * step_size.
std::uint64_t firstWrenchStep(double start_time, double step_size, std::uint64_t next);

// One step of a creature; `number` is the world's step count after it (for the watchdog's
// verdict).
void stepCreature(CreatureRecord& record, CreatureSim& sim, const StepContext& context,
                  std::uint64_t number);

}  // namespace flapsim
