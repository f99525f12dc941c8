#include "world/joint_drives.h"

#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "dynamics/creature_body.h"
#include "dynamics/motor.h"
#include "flapsim/world.h"

namespace flapsim {

namespace {

// The child link's own inertia about the joint axis (its mass, if prismatic): a lower bound
// of what the joint moves.
double childInertia(const CreatureModel& m, const JointModel& j) {
  const LinkModel& child = m.links[j.child_link];
  if (j.type == JointType::kPrismatic) return child.mass;
  const Vec3 r = child.com - child.com.dot(j.axis) * j.axis;  // COM off the axis
  return child.inertia.dot(j.axis.cwiseAbs2()) + child.mass * r.squaredNorm();
}

}  // namespace

double dampingLimit(const CreatureModel& m, const JointModel& j, double dt) {
  return 0.25 * childInertia(m, j) / dt;
}

double stiffnessLimit(const CreatureModel& m, const JointModel& j, double dt) {
  return 0.25 * childInertia(m, j) / (dt * dt);
}

std::vector<std::string> cappedJointValues(const CreatureModel& model, double step_size) {
  std::vector<std::string> out;
  auto note = [&](const JointModel& j, const char* what, double value, double used) {
    std::ostringstream line;
    line.precision(4);
    line << "joint '" << j.name << "': " << what << " " << value
         << " is more than an explicit step of " << step_size << " s keeps stable; " << used
         << " is used";
    out.push_back(line.str());
  };
  for (const JointModel& j : model.joints) {
    if (!j.movable()) continue;
    const double damping = dampingLimit(model, j, step_size);
    const double stiffness = stiffnessLimit(model, j, step_size);
    if (j.damping > damping) note(j, "damping", j.damping, damping);
    if (j.stiffness > stiffness) note(j, "spring stiffness", j.stiffness, stiffness);
  }
  return out;
}

namespace {

// A servo on the joint to `joint_link` with target velocity `target` and torque bound
// `effort`.
void demand(CreatureBody& b, int joint_link, double target, double effort, double dt) {
  ServoDemand& d = b.demands[joint_link];
  d.active = true;
  d.max_impulse = effort * dt;
  b.servo_target[joint_link] = target;
}

// The motor of joint `j` (index `ji`) driving it towards velocity `target`: bounded by its
// torque-speed line at the joint's velocity if it has a <motor>, else by its flat effort.
void motorDemand(const JointModel& j, size_t ji, CreatureBody& b, double target, double dt) {
  demand(b, j.child_link, target, b.max_effort[ji], dt);
  if (j.motor) {
    const TorqueBounds bounds = motorTorqueBounds(*j.motor, b.mb->getJointVel(j.child_link - 1));
    ServoDemand& d = b.demands[j.child_link];
    d.max_impulse = bounds.positive * dt;
    d.max_negative_impulse = bounds.negative * dt;
  }
}

void driveJoint(const JointModel& j, size_t ji, JointDrive& d, CreatureBody& b, double dt) {
  btMultiBody* mb = b.mb.get();
  const int link = j.child_link - 1;
  b.demands[j.child_link].active = false;
  b.demands[j.child_link].max_negative_impulse = -1.0;
  switch (d.mode) {
    case JointDrive::Mode::kStroke:
      motorDemand(j, ji, b, d.stroke.target(mb->getJointPos(link), dt), dt);
      break;
    case JointDrive::Mode::kVelocity:
      motorDemand(j, ji, b, d.velocity, dt);
      break;
    case JointDrive::Mode::kPassive:
      // Coulomb friction: a zero-velocity servo whose torque is capped by friction.
      if (j.friction > 0.0) demand(b, j.child_link, 0.0, j.friction, dt);
      if (b.damping[ji] > 0.0) mb->addJointTorque(link, -b.damping[ji] * mb->getJointVel(link));
      break;
  }
  // A spring acts whether or not a motor drives the joint (in parallel with it).
  if (b.stiffness[ji] > 0.0) {
    mb->addJointTorque(link, -b.stiffness[ji] * (mb->getJointPos(link) - j.reference));
  }
}

// Feathering: a stroking wing pitches its feather joint to the stroke's feather angle
// (StrokeGenerator::featherTarget: a triangle stroke's per half-stroke, approached with the
// time constant kFeatherTime; a sine stroke's smooth turn, followed step by step).
void driveFeathers(const CreatureModel& m, const std::vector<JointDrive>& drives, CreatureBody& b,
                   double dt) {
  for (int wi : m.wing_joints) {
    const JointModel& wing = m.joints[wi];
    const JointDrive& d = drives[wi];
    if (wing.feather_joint < 0 || d.mode != JointDrive::Mode::kStroke) continue;
    const JointModel& feather = m.joints[wing.feather_joint];
    const double error = d.stroke.featherTarget() - b.mb->getJointPos(feather.child_link - 1);
    const double time = d.stroke.command().shape == StrokeShape::kSine ? dt : kFeatherTime;
    motorDemand(feather, static_cast<size_t>(wing.feather_joint), b, error / time, dt);
  }
}

}  // namespace

StrokeTurn strokeTurn(const CreatureModel& m, const std::vector<JointDrive>& drives,
                      const CreatureBody& b, double dt) {
  StrokeTurn turn;
  turn.first_turn = dt;
  for (int ji : m.wing_joints) {
    const JointDrive& d = drives[ji];
    if (d.mode != JointDrive::Mode::kStroke) continue;
    const int k = m.joints[ji].child_link;
    if (static_cast<size_t>(k) < b.solution.saturated.size() && b.solution.saturated[k]) {
      turn.reversing = true;
    }
    const double t = d.stroke.timeToTurn(b.mb->getJointPos(k - 1));
    if (t <= dt) {
      turn.reversing = true;
      turn.first_turn = std::min(turn.first_turn, t);
    }
  }
  return turn;
}

void applyDrives(const CreatureModel& m, std::vector<JointDrive>& drives, CreatureBody& b,
                 double dt) {
  for (size_t ji = 0; ji < m.joints.size(); ++ji) {
    const JointModel& j = m.joints[ji];
    if (j.movable()) driveJoint(j, ji, drives[ji], b, dt);
  }
  driveFeathers(m, drives, b, dt);
}

}  // namespace flapsim
