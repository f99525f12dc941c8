// The power meter of a creature's motors: per joint, each (sub)step's motor impulse times the
// joint's displacement in it, summed into the counters of flapsim::CreaturePower. Private
// to flapsim_core.
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <vector>

#include "dynamics/joint_servo.h"
#include "dynamics/motor.h"
#include "flapsim/world.h"
#include "world/joint_drives.h"

namespace flapsim {

class PowerMeter {
 public:
  /// Zero counters for a creature of `joints` joints.
  void reset(size_t joints);
  /// Before a step: its work starts at zero (and can be taken back).
  void beginStep();
  /// Before a (sub)step of `mb`: the joint positions it starts from.
  void beginSubStep(const CreatureModel& m, const btMultiBody& mb);
  /// After it: each motor's work in it (the servo impulses of `servos` over `h`).
  void endSubStep(const CreatureModel& m, const std::vector<JointDrive>& drives,
                  const btMultiBody& mb, const ServoSolution& servos, double h);
  /// After the last substep of a step of `dt`: the step counts.
  void endStep(double dt);
  /// The step did not happen (the watchdog put the creature back): its work is taken back.
  void undoStep();
  /// The counters, as World::power gives them.
  CreaturePower report(double mass) const;

 private:
  std::vector<JointEnergy> energy_;
  std::vector<JointEnergy> before_;     // energy_ at the start of the step
  std::vector<double> step_work_;       // per joint, in the current step
  std::vector<double> start_;           // per joint, its position at the start of the substep
  std::vector<double> start_velocity_;  // ... and its velocity
  double time_ = 0.0;
  double last_step_ = 0.0;
};

}  // namespace flapsim
