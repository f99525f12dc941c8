// A creature's step as named stages, after MuJoCo's mj_step. One step of `step_size`:
//
//   check       a creature the watchdog froze is not stepped; the state before the step is
//               kept (creature_step.cpp: stepCreature)
//   air         the air's velocity at the root's COM (wind, gust, turbulence), uniform over
//               the creature for the step (creatureAirVelocity)
//   substeps    a step in which a wing reverses is cut at the turn into pieces of at most
//               turn_substep (world/joint_drives.h: strokeTurn); each (sub)step runs:
//     position      the link frames of the (sub)step's start: those the last one ended with
//                   (dynamics/bullet_body.h), and the momentum and velocities then
//                   (dynamics/momentum_balance.h, dynamics/servo_stage.h: begin)
//     actuation     joint drives -> servo demands and passive torques (world/joint_drives.h)
//     fluid         the air's wrenches and this step's implicit fluid (world/fluid_stage.h)
//     external      the user's external wrenches (this file)
//     dynamics      Bullet's step: unconstrained accelerations (its articulated-body pass or
//                   dynamics/tree_dynamics.h), then inside it the servo stage solves servos
//                   and the implicit fluid together (dynamics/servo_stage.h: solve), then
//                   contacts and joint limits (dynamics/joint_limit.h), then integration
//     integrate     saturated servos move by the trapezoid of their velocities
//                   (dynamics/servo_stage.h: integrateSaturated)
//     momentum      the rigid correction that keeps the momentum that of the external
//                   impulses, and the frames of the (sub)step's end (momentum_balance.h: end)
//   wrenches    the external wrenches count down their steps
//   watchdog    a non-finite or too fast result is refused: the creature is put back as it
//               was and frozen (dynamics/bullet_body.h: motionFault)
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

// One step of a creature; `number` is the world's step count after it (for the watchdog's
// verdict).
void stepCreature(CreatureRecord& record, CreatureSim& sim, const StepContext& context,
                  std::uint64_t number);

}  // namespace flapsim
