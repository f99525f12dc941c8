// The energy audit of a creature (World::setEnergyAudit, World::energy): the work of the air
// and of the joints' damping, summed over the (sub)steps while the audit is on, and the
// energies of its state. Works are taken by the trapezoid of each (sub)step's start and end
// velocities, which is what the step's velocity change makes of a force held over it: the
// end's velocity of the point the force held at (the COM at the start) composed as the step
// composed it, from the root's velocity and the joints' rates with the joints' axes of the
// start (a link turning about a fixed hinge does no work against a force that its start's
// motion does none against); the energies are those of the fluid's frame (velocities
// relative to the wind). Private to flapsim_core.
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <vector>

#include "dynamics/bullet_body.h"
#include "dynamics/spatial.h"
#include "flapsim/world.h"
#include "world/joint_drives.h"

namespace flapsim {

class CreatureFluid;
class ServoStage;

class EnergyMeter {
 public:
  // Before a (sub)step: the root COM it starts from and every joint's axis (the joints'
  // velocities then are the servo stage's, ServoStage::startVelocity).
  void beginSubStep(const CreatureModel& m, const BulletBody& body);
  // After it (`air`: the fluid stage ran): the air's work on every aero body (its explicit
  // wrench and the implicit drag's impulse) and the damping's on every passive joint.
  void endSubStep(const CreatureModel& m, const std::vector<JointDrive>& drives,
                  const BulletBody& body, const CreatureFluid& fluid, const ServoStage& servos,
                  bool air, const Vec3& wind, double h);
  double airWork() const { return air_work_; }
  double dampingWork() const { return damping_work_; }

 private:
  // The spatial velocity at the end of the (sub)step, at `point`, of link `link` as the step
  // composed it: the root's with the start's root COM, and each joint's rate on its start's
  // axis.
  // `root`: the root's kinematics at the end.
  void endVelocity(const CreatureModel& m, const btMultiBody& mb, const BodyKinematics& root,
                   int link, const Vec3& point, Vec3& linear, Vec3& angular) const;

  double air_work_ = 0.0;
  double damping_work_ = 0.0;
  Vec3 origin_ = Vec3::Zero();   // the root COM at the start of the (sub)step
  std::vector<JointAxis> axes_;  // per joint of the model, at the start of the (sub)step
};

// The energies of a creature's state (CreatureEnergy's kinetic, potential, spring and fluid
// kinetic parts), in the frame of a fluid moving at `air.wind`. The velocities after a
// semi-implicit (sub)step of `piece` are the mean over it (the positions moved by piece x
// them): its kinetic energy is that of the (sub)step's middle, and the potential is taken
// there too, at each COM less piece / 2 x its velocity (0 before any step: the velocities
// are the state's own). At the end's positions a free fall at 1 ms would lose g^2 h / 2 per
// kg and second, 0.1 J/kg in 2 s, which is the two instants' difference, not a loss.
void stateEnergies(const CreatureModel& m, const BulletBody& body, const CreatureFluid& fluid,
                   const ServoStage& servos, const AirParams& air, const Vec3& gravity,
                   double piece, CreatureEnergy& out);

}  // namespace flapsim
