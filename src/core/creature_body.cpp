#include "creature_body.h"

namespace flapsim {

BodyKinematics LinkFrames::kinematics(int k) const {
  const btQuaternion to_world = world_to_local[k].inverse();
  BodyKinematics kin;
  kin.orientation = fromBt(to_world);
  kin.com = fromBt(local_origin[k]);
  kin.linear_velocity = fromBt(quatRotate(to_world, vel[k]));
  kin.angular_velocity = fromBt(quatRotate(to_world, omega[k]));
  return kin;
}

CreatureBody::~CreatureBody() {
  if (!scene) return;
  btMultiBodyDynamicsWorld& world = scene->world();
  for (auto& l : limits) world.removeMultiBodyConstraint(l.get());
  for (auto& c : colliders) world.removeCollisionObject(c.get());
  if (mb) world.removeMultiBody(mb.get());
}

void CreatureBody::updateKinematics() {
  mb->forwardKinematics(frames.world_to_local, frames.local_origin);
  mb->compTreeLinkVelocities(frames.omega.data(), frames.vel.data());
}

LinkFrames CreatureBody::currentFrames() const {
  // btMultiBody::forwardKinematics, step for step, but from const accessors only (it also
  // writes Bullet's cached link transforms).
  const btMultiBody& m = *mb;
  const int n = m.getNumLinks();
  LinkFrames f;
  f.world_to_local.resize(n + 1);
  f.local_origin.resize(n + 1);
  f.world_to_local[0] = m.getWorldToBaseRot();
  f.local_origin[0] = m.getBasePos();
  for (int k = 0; k < n; ++k) {
    const int parent = m.getParent(k);
    f.world_to_local[k + 1] = m.getParentToLocalRot(k) * f.world_to_local[parent + 1];
    f.local_origin[k + 1] =
        f.local_origin[parent + 1] + quatRotate(f.world_to_local[k + 1].inverse(), m.getRVector(k));
  }
  f.omega.resize(n + 1);
  f.vel.resize(n + 1);
  m.compTreeLinkVelocities(f.omega.data(), f.vel.data());
  return f;
}

bool CreatureBody::mayTouch() const {
  if (!scene->hasGround()) return false;
  if (scene->hasContacts()) return true;
  constexpr double kClearance = 0.1;  // m: well beyond Bullet's contact margins
  const double dt = scene->timeStep();
  for (size_t k = 0; k < reach.size(); ++k) {
    if (reach[k] <= 0.0) continue;
    const double travel = 2.0 * dt * (frames.vel[k].length() + frames.omega[k].length() * reach[k]);
    if (frames.local_origin[static_cast<int>(k)].z() - reach[k] - travel < kClearance) {
      return true;
    }
  }
  return false;
}

// Inertias, COMs, axes and anchors of the servo links in the world frame, relative to the
// root's COM.
void CreatureBody::updateServoLinks() {
  const CreatureModel& m = *model;
  const btVector3 origin = frames.local_origin[0];  // the root's COM
  for (size_t k = 0; k < servo_links.size(); ++k) {
    const LinkModel& l = m.links[k];
    ServoLink& s = servo_links[k];
    const btMatrix3x3 rot(frames.world_to_local[k].inverse());
    const btMatrix3x3 inertia = rot.scaled(toBt(l.inertia)) * rot.transpose();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) s.inertia(r, c) = inertia[r][c];
    }
    s.com = fromBt(frames.local_origin[k] - origin);
    if (k > 0) {
      const JointModel& j = m.joints[l.parent_joint];
      s.axis = fromBt(rot * toBt(j.axis));
      s.anchor = fromBt(frames.local_origin[k] - rot * toBt(l.com) - origin);
    }
  }
}

void CreatureBody::applyServos() {
  bool any = false;
  for (size_t k = 1; k < demands.size(); ++k) {
    if (!demands[k].active) continue;
    demands[k].velocity_change = servo_target[k] - mb->getJointVel(static_cast<int>(k) - 1);
    any = true;
  }
  if (!any) {
    solution.impulse.assign(demands.size(), 0.0);
    return;
  }
  updateServoLinks();
  servo.solve(servo_links, model->fixed_base, demands, solution);
  for (size_t k = 1; k < demands.size(); ++k) {
    if (servo_links[k].joint == ServoJointType::kFixed) continue;
    const int link = static_cast<int>(k) - 1;
    mb->setJointVel(link, mb->getJointVel(link) + solution.velocity_change[k]);
  }
  if (!model->fixed_base) {
    const Vec6& dv = solution.root_velocity_change;
    mb->setBaseOmega(mb->getBaseOmega() + toBt(Vec3(dv.head<3>())));
    mb->setBaseVel(mb->getBaseVel() + toBt(Vec3(dv.tail<3>())));
  }
}

}  // namespace flapsim
