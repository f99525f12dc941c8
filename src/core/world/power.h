// The power meter of a creature's motors: per joint, each (sub)step's motor work (what the joint
// transmits, world/transmitted_work.h, or the servo's impulse times the mean of the joint's start
// and end velocities: WorldParams::motor_work), summed into the counters of
// flapsim::CreaturePower.
// Private to flapsim_core.
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <vector>

#include "dynamics/motor.h"
#include "dynamics/servo_stage.h"
#include "flapsim/world.h"
#include "world/joint_drives.h"
#include "world/transmitted_work.h"

namespace flapsim {

class PowerMeter {
 public:
  /// Zero counters for a creature of `joints` joints.
  void reset(size_t joints);
  /// Before a step: its work starts at zero (and can be taken back).
  void beginStep();
  /// After a (sub)step of `h`: each motor at work in it (its servo's impulse in the last solve
  /// of `servos` not zero) did the work `transmitted` gives if not null and known, else its
  /// impulse over the velocities from its start, ServoStage::startVelocity, to `mb`'s.
  void endSubStep(const CreatureModel& m, const std::vector<JointDrive>& drives,
                  const btMultiBody& mb, const ServoStage& servos,
                  const TransmittedWork* transmitted, double h);
  /// After the last substep of a step of `dt`: the step counts.
  void endStep(double dt);
  /// The step did not happen (the watchdog put the creature back): its work is taken back.
  void undoStep();
  /// Per joint, its motor's work in the current step so far (after endStep(): the step's).
  const std::vector<double>& stepWork() const { return step_work_; }
  /// The counters, as World::power gives them.
  CreaturePower report(double mass) const;

 private:
  std::vector<JointEnergy> energy_;
  std::vector<JointEnergy> before_;  // energy_ at the start of the step
  std::vector<double> step_work_;    // per joint, in the current step
  double time_ = 0.0;
  double last_step_ = 0.0;
};

}  // namespace flapsim
