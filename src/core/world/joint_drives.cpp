#include "world/joint_drives.h"

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "dynamics/bullet_scene.h"
#include "dynamics/motor.h"
#include "dynamics/servo_stage.h"

namespace flapsim {

namespace {

// The motor of joint `j` (index `ji`) driving it towards velocity `target`: bounded by its
// torque-speed line at the joint's velocity if it has a <motor>, else by its flat effort.
void motorDemand(const JointModel& j, size_t ji, ServoStage& servos, const btMultiBody& mb,
                 double target, double dt) {
  const TorqueBounds bounds = j.motor
                                  ? motorTorqueBounds(*j.motor, mb.getJointVel(j.child_link - 1))
                                  : flatTorqueBounds(servos.maxEffort(ji));
  servos.demand(j.child_link, target, bounds, dt);
}

void driveJoint(const JointModel& j, size_t ji, JointDrive& d, ServoStage& servos, btMultiBody& mb,
                double dt) {
  const int link = j.child_link - 1;
  servos.release(j.child_link);
  switch (d.mode) {
    case JointDrive::Mode::kStroke:
      motorDemand(j, ji, servos, mb, d.stroke.target(mb.getJointPos(link), dt), dt);
      break;
    case JointDrive::Mode::kVelocity:
      motorDemand(j, ji, servos, mb, d.velocity, dt);
      break;
    case JointDrive::Mode::kHold:
      motorDemand(j, ji, servos, mb, (d.position - mb.getJointPos(link)) / kHoldTime, dt);
      break;
    case JointDrive::Mode::kPassive:
      // Coulomb friction: a zero-velocity servo whose torque is capped by friction.
      if (j.friction > 0.0) servos.demand(j.child_link, 0.0, j.friction, dt);
      if (servos.damping(ji) > 0.0 && !servos.implicitSpring(ji)) {
        mb.addJointTorque(link, -servos.damping(ji) * mb.getJointVel(link));
      }
      break;
  }
  // A spring acts whether or not a motor drives the joint (in parallel with it); a stiff one
  // in the servo solve (ServoStage::implicitSpring).
  if (servos.stiffness(ji) > 0.0 && !servos.implicitSpring(ji)) {
    mb.addJointTorque(link, -servos.stiffness(ji) * (mb.getJointPos(link) - j.reference));
  }
}

// Feathering: a stroking wing pitches its feather joint to the stroke's feather angle
// (StrokeGenerator::featherTarget: a triangle stroke's per half-stroke, approached with the
// time constant kFeatherTime; a sine stroke's smooth turn, followed step by step).
void driveFeathers(const CreatureModel& m, const std::vector<JointDrive>& drives,
                   ServoStage& servos, const btMultiBody& mb, double dt) {
  for (int wi : m.wing_joints) {
    const JointModel& wing = m.joints[wi];
    const JointDrive& d = drives[wi];
    if (wing.feather_joint < 0 || d.mode != JointDrive::Mode::kStroke) continue;
    const JointModel& feather = m.joints[wing.feather_joint];
    const double error = d.stroke.featherTarget() - mb.getJointPos(feather.child_link - 1);
    const double time = d.stroke.command().shape == StrokeShape::kSine ? dt : kFeatherTime;
    motorDemand(feather, static_cast<size_t>(wing.feather_joint), servos, mb, error / time, dt);
  }
}

}  // namespace

StrokeTurn strokeTurn(const CreatureModel& m, const std::vector<JointDrive>& drives,
                      const ServoStage& servos, const btMultiBody& mb, double dt) {
  StrokeTurn turn;
  turn.first_turn = dt;
  for (int ji : m.wing_joints) {
    const JointDrive& d = drives[ji];
    if (d.mode != JointDrive::Mode::kStroke) continue;
    const int k = m.joints[ji].child_link;
    if (servos.saturated(static_cast<size_t>(k))) turn.reversing = true;
    const double t = d.stroke.timeToTurn(mb.getJointPos(k - 1));
    if (t <= dt) {
      turn.reversing = true;
      turn.first_turn = std::min(turn.first_turn, t);
    }
  }
  return turn;
}

void applyDrives(const CreatureModel& m, std::vector<JointDrive>& drives, ServoStage& servos,
                 btMultiBody& mb, double dt) {
  for (size_t ji = 0; ji < m.joints.size(); ++ji) {
    const JointModel& j = m.joints[ji];
    if (j.movable()) driveJoint(j, ji, drives[ji], servos, mb, dt);
  }
  driveFeathers(m, drives, servos, mb, dt);
}

}  // namespace flapsim
