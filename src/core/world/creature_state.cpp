#include "world/creature_state.h"

namespace flapsim {

Motion linkMotion(const Pose& pose, const Twist& twist, const Pose& frame) {
  const bool same =
      frame.position == Vec3::Zero() && frame.orientation.coeffs() == Quat::Identity().coeffs();
  if (same) return Motion{pose, twist};
  const Pose link = Pose{pose.position, pose.orientation.normalized()} * frame.inverse();
  return Motion{link, Twist{twist.linear + twist.angular.cross(link.position - pose.position),
                            twist.angular}};
}

bool frameMotion(const CreatureModel& model, const CreatureState& state, const std::string& name,
                 Pose* pose, Twist* twist) {
  const int k = name.empty() ? 0 : model.findLink(name);
  if (k >= 0) {
    if (pose) *pose = state.link_poses.at(k);
    if (twist) *twist = state.link_twists.at(k);
    return true;
  }
  for (const LumpedLink& l : model.lumped) {
    if (l.name != name) continue;
    const Pose& host = state.link_poses.at(l.link);  // its URDF frame
    const Pose at = host * l.pose;
    const Twist& t = state.link_twists.at(l.link);
    if (pose) *pose = at;
    if (twist) *twist = Twist{t.linear + t.angular.cross(at.position - host.position), t.angular};
    return true;
  }
  return false;
}

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
    s.link_poses[k] = m.links[k].toUrdf(Pose{origin, q});  // the link frame's origin
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
  const FrameOnLink frame =
      request.link.empty() ? FrameOnLink{0, m.links[0].urdf_frame} : m.findFrame(request.link);
  const int k = frame.link;
  if (k < 0) throw InputError("creature '" + name + "' has no link '" + request.link + "'");
  const Motion link = linkMotion(request.pose, request.twist, frame.pose);
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
  const Quat q = link.pose.orientation.normalized();
  const Pose wanted{link.pose.position + q * m.links[k].com, q};  // link k's COM frame
  const Pose base = k == 0 ? wanted : wanted * Pose{rel.com, rel.orientation}.inverse();
  mb.setBaseWorldTransform(toBt(base));
  sim.body.updateKinematics();
  // Velocities are linear in the base twist and the joint rates: the base twist is what
  // the wanted one lacks after the joints' share (base at rest).
  const BodyKinematics now = sim.body.frames().kinematics(k);
  const Vec3 omega = link.twist.angular - now.angular_velocity;
  const Vec3 com_velocity =
      link.twist.linear + link.twist.angular.cross(now.com - link.pose.position);
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
