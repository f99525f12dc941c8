// One creature of a world: what the user asked for (enough to rebuild it bit for bit), and its
// body with the state of each stage of a step, rebuilt from that record on reset. The step
// itself, stage by stage, is world/creature_step.h. Private to flapsim_core.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dynamics/bullet_body.h"
#include "dynamics/momentum_balance.h"
#include "dynamics/servo_stage.h"
#include "flapsim/turbulence.h"
#include "flapsim/world.h"
#include "fluid/creature_fluid.h"
#include "world/energy_meter.h"
#include "world/joint_drives.h"
#include "world/power.h"
#include "world/step_record.h"

namespace flapsim {

// An external wrench while it acts: the force's point in the link's COM frame.
struct ActiveWrench {
  int link = 0;
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero(), offset = Vec3::Zero();
  std::int64_t steps_left = -1;  // < 0: until cleared
  double start_time = 0.0;       // s: acts from the first step starting at or after it
  bool started = false;          // decided at each step's start (creature_step.cpp)
};

// What the user asked for, and what the world found.
struct CreatureRecord {
  std::string name;
  CreatureModelPtr model;
  Pose pose;
  Twist twist;
  std::vector<JointDrive> drives;         // per model joint
  std::optional<Divergence> divergence;   // set by the watchdog: not stepped until reset
  bool reported = false;                  // handed out by takeDivergences()
  std::vector<ActiveWrench> wrenches;     // external, in the order applied
  Vec3 root_acceleration = Vec3::Zero();  // of the root's COM over the last step
};

// The body and the state of every stage: each part is written by its own methods only.
class CreatureSim {
 public:
  // A creature of model `m` (which must outlive it) with its root link frame at `pose`
  // moving with `twist`.
  CreatureSim(const CreatureModel& m, const Pose& pose, const Twist& twist,
              const WorldParams& params);
  CreatureSim(const CreatureSim&) = delete;
  CreatureSim& operator=(const CreatureSim&) = delete;

  BulletBody body;              // the multibody, its scene and the link frames
  ServoStage servos;            // joint servos and the fluid's implicit part
  CreatureFluid fluid;          // the aero bodies
  MomentumBalance momentum;     // the momentum carried from step to step
  BodySnapshot before;          // the state before the current step (the watchdog's)
  PowerMeter power;             // the work of its motors since it was built
  TransmittedWork transmitted;  // what its joints transmit in a (sub)step (MotorWorkMeter)
  EnergyMeter energy;           // the air's and damping's work while the audit is on
  TurbulenceField turbulence;   // its realisation of the air's turbulence (none if off)
  StepRecord record;            // the step data of its last step, as the stages wrote it
  double last_piece = 0.0;      // s: its last (sub)step's length (0: none since it settled)

  // After the multibody's state was set from outside a step: what comes next depends on
  // the new state alone, as for a body just built (and no step data).
  void settle();
};

// The energy audit of creature `m` in `sim` (World::energy).
CreatureEnergy creatureEnergy(const CreatureModel& m, const CreatureSim& sim,
                              const WorldParams& params);

}  // namespace flapsim
