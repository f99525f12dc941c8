#include "world/creature_state.h"

namespace flapsim {

CreatureState readState(const CreatureModel& m, const CreatureSim& sim) {
  const LinkFrames frames = sim.body.currentFrames();
  CreatureState s;
  const size_t n = m.links.size();
  s.link_poses.resize(n);
  s.link_twists.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const BodyKinematics kin = frames.kinematics(static_cast<int>(k));
    const Quat q = kin.orientation.normalized();
    const Vec3 origin = kin.com - q * m.links[k].com;
    s.link_poses[k] = Pose{origin, q};
    s.link_twists[k] = Twist{kin.linear_velocity + kin.angular_velocity.cross(origin - kin.com),
                             kin.angular_velocity};
  }
  s.joint_positions.assign(m.joints.size(), 0.0);
  s.joint_velocities.assign(m.joints.size(), 0.0);
  s.joint_efforts.assign(m.joints.size(), 0.0);
  const btMultiBody& mb = sim.body.multiBody();
  for (size_t j = 0; j < m.joints.size(); ++j) {
    if (!m.joints[j].movable()) continue;
    const int k = m.joints[j].child_link;
    s.joint_positions[j] = mb.getJointPos(k - 1);
    s.joint_velocities[j] = mb.getJointVel(k - 1);
    s.joint_efforts[j] = sim.servos.effort(static_cast<size_t>(k));
  }
  return s;
}

void placeCreature(const std::string& name, const CreatureModel& m, CreatureSim& sim,
                   const StateRequest& request, double max_speed) {
  const int k = request.link.empty() ? 0 : m.findLink(request.link);
  if (k < 0) throw InputError("creature '" + name + "' has no link '" + request.link + "'");
  if (m.fixed_base &&
      (k != 0 || request.twist.linear != Vec3::Zero() || request.twist.angular != Vec3::Zero())) {
    throw InputError("creature '" + name +
                     "' has a fixed base: only its root's pose can be set, with a zero twist");
  }
  btMultiBody& mb = sim.body.multiBody();
  BodySnapshot before;
  before.take(mb);
  for (size_t j = 0; j < m.joints.size(); ++j) {
    if (!m.joints[j].movable()) continue;
    const int l = m.joints[j].child_link - 1;
    if (!request.joint_positions.empty()) mb.setJointPos(l, request.joint_positions[j]);
    if (!request.joint_velocities.empty()) mb.setJointVel(l, request.joint_velocities[j]);
  }
  // Link k relative to the root (base at the origin, at rest): the base follows from it,
  // and the result does not depend on where the creature was.
  mb.setBaseWorldTransform(toBt(Pose()));
  mb.setBaseVel(btVector3(0, 0, 0));
  mb.setBaseOmega(btVector3(0, 0, 0));
  sim.body.updateKinematics();
  const BodyKinematics rel = sim.body.frames().kinematics(k);
  const Quat q = request.pose.orientation.normalized();
  const Pose wanted{request.pose.position + q * m.links[k].com, q};  // link k's COM frame
  const Pose base = k == 0 ? wanted : wanted * Pose{rel.com, rel.orientation}.inverse();
  mb.setBaseWorldTransform(toBt(base));
  sim.body.updateKinematics();
  // Velocities are linear in the base twist and the joint rates: the base twist is what
  // the wanted one lacks after the joints' share (base at rest).
  const BodyKinematics now = sim.body.frames().kinematics(k);
  const Vec3 omega = request.twist.angular - now.angular_velocity;
  const Vec3 com_velocity =
      request.twist.linear + request.twist.angular.cross(now.com - request.pose.position);
  const Vec3 velocity = com_velocity - omega.cross(now.com - base.position) - now.linear_velocity;
  if (!m.fixed_base) {
    mb.setBaseVel(toBt(velocity));
    mb.setBaseOmega(toBt(omega));
  }
  sim.body.updateKinematics();
  const std::string fault = sim.body.motionFault(max_speed);
  if (!fault.empty()) {
    before.restore(mb);
    sim.settle();
    throw InputError("creature '" + name + "': state refused, " + fault);
  }
  sim.settle();
}

}  // namespace flapsim
