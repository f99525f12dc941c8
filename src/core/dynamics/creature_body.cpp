#include "dynamics/creature_body.h"

#include <algorithm>
#include <cmath>

#include "fluid/added_mass.h"

namespace flapsim {

BodyKinematics LinkFrames::kinematics(int k, Mat3* rotation) const {
  BodyKinematics kin;
  kin.orientation = fromBt(world_to_local[k].inverse());
  // One rotation matrix for both velocities: cheaper than two quaternion rotations.
  const Mat3 r = kin.orientation.toRotationMatrix();
  kin.com = fromBt(local_origin[k]);
  // Bullet's link velocities are in the link's (COM) frame.
  kin.body_linear_velocity = fromBt(vel[k]);
  kin.body_angular_velocity = fromBt(omega[k]);
  kin.linear_velocity = r * kin.body_linear_velocity;
  kin.angular_velocity = r * kin.body_angular_velocity;
  kin.rotation = r;
  kin.has_body_frame = true;
  if (rotation) *rotation = r;
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
  const btMultiBody& m = *mb;
  const int n = m.getNumLinks();
  LinkFrames f;
  multiBodyFrames(m, f.world_to_local, f.local_origin);
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
    // The travel below is at most 2 dt sqrt(2 (v^2 + (w reach)^2)): well clear of that (as
    // high in the air), no square roots.
    const double margin = frames.local_origin[static_cast<int>(k)].z() - reach[k] - kClearance;
    const double w_reach = frames.omega[k].length2() * reach[k] * reach[k];
    if (margin > 0.0 &&
        8.0 * dt * dt * (frames.vel[k].length2() + w_reach) < 0.99 * margin * margin) {
      continue;
    }
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

void CreatureBody::velocityChanges(const ServoTree& tree) {
  const size_t n = servo_links.size();
  change_of_link_.resize(n);
  // The root's [angular; linear of its COM], which is the point the spatial velocities are
  // taken at.
  change_of_link_[0] << fromBt(mb->getBaseOmega()) - start_base_omega_,
      fromBt(mb->getBaseVel()) - start_base_velocity_;
  for (size_t k = 1; k < n; ++k) {
    const ServoLink& l = servo_links[k];
    change_of_link_[k] = change_of_link_[l.parent];
    if (l.joint == ServoJointType::kFixed) continue;
    const int link = static_cast<int>(k) - 1;
    const double dq = jointVel(*mb, link) - start_joint_velocity_[link];
    change_of_link_[k] += (tree.subspace ? (*tree.subspace)[k] : motionSubspace(l)) * dq;
  }
}

void CreatureBody::applyServos() {
  bool any = false;
  for (size_t k = 1; k < demands.size(); ++k) {
    if (!demands[k].active) continue;
    demands[k].velocity_change = servo_target[k] - jointVel(*mb, static_cast<int>(k) - 1);
    any = true;
  }
  drag_impulse_.setZero();
  if (!any && !fluid_active) {
    solution.impulse.assign(demands.size(), 0.0);
    solution.saturated.assign(demands.size(), false);
    return;
  }
  // A lean step has the links' inertias and joint subspaces already (same frame and origin).
  ServoTree tree;
  if (const TreeDynamics* lean = scene->world().leanTree()) {
    tree.inertia = &lean->bodyInertias();
    tree.subspace = &lean->jointAxes();
  } else {
    updateServoLinks();
  }
  if (fluid_active) {
    // (M + A) (v1 - v0) = M (vb - v0) + servo impulses, with A the fluid's implicit part
    // and vb Bullet's velocities after this step's forces: solved for v1 - vb, it is the
    // tree with inertia M + A under the impulses -A (vb - v0) on the aero bodies.
    const size_t n = servo_links.size();
    velocityChanges(tree);
    // Only the aero bodies with implicit drag or added mass have loads (loads_.links).
    loads_.extra_inertia.resize(n);
    loads_.impulse.resize(n);
    loads_.links.clear();
    drag_.resize(aero.size());
    change_.resize(aero.size());
    for (size_t i = 0; i < aero.size(); ++i) {
      const int k = aero[i].link;
      change_[i] = change_of_link_[k];
      if (aero[i].drag_zero && !aero[i].has_added_mass) continue;
      loads_.links.push_back(k);
      const Vec3 offset = fromBt(frames.local_origin[k] - frames.local_origin[0]);
      Mat6& extra = loads_.extra_inertia[k];
      extra.setZero();
      if (!aero[i].drag_zero) {
        drag_[i] = spatialToCommonFrame(aero[i].drag, Quat::Identity(), offset);
        extra += drag_[i];
      }
      if (aero[i].has_added_mass) addFactorMatrix(aero[i].added, offset, extra);
      loads_.impulse[k] = -extra * change_[i];
    }
    servo.solve(servo_links, model->fixed_base, demands, loads_, tree, solution);
    // The implicit drag's impulse over the step, -step D (v1 - v0) on each aero body (the
    // added mass is part of the momentum itself: see measureMomentum()).
    for (size_t i = 0; i < aero.size(); ++i) {
      if (aero[i].drag_zero) continue;
      drag_impulse_ -= drag_[i] * (change_[i] + solution.link_velocity_change[aero[i].link]);
    }
  } else {
    servo.solve(servo_links, model->fixed_base, demands, ServoLoads(), tree, solution);
  }
  for (size_t k = 1; k < demands.size(); ++k) {
    if (servo_links[k].joint == ServoJointType::kFixed) continue;
    const int link = static_cast<int>(k) - 1;
    mb->setJointVel(link, jointVel(*mb, link) + solution.velocity_change[k]);
  }
  if (!model->fixed_base) {
    const Vec6& dv = solution.root_velocity_change;
    mb->setBaseOmega(mb->getBaseOmega() + toBt(Vec3(dv.head<3>())));
    mb->setBaseVel(mb->getBaseVel() + toBt(Vec3(dv.tail<3>())));
  }
}

const SpatialFactor& CreatureBody::turnedAddedMass(AeroBody& a, const Mat3& rotation) const {
  if (!a.added_valid || a.added_density != added_mass_density_ || a.added_rotation != rotation) {
    if (added_mass_density_ <= 0.0 || !a.has_added_mass) {
      a.added.any = false;
    } else {
      turnFactor(a.added_factor, rotation, added_mass_density_, a.added);
    }
    a.added_rotation = rotation;
    a.added_density = added_mass_density_;
    a.added_valid = true;
  }
  return a.added;
}

SystemMomentum CreatureBody::measureMomentum() {
  TreeDynamics& tree = scene->world().tree();
  tree.updateFrames(*mb);
  const auto& velocity = tree.velocities(*mb);
  const auto& com = tree.coms();
  const auto& inertia = tree.bodyInertias();
  const Vec3 base = fromBt(mb->getBasePos());
  // Sums about the base's COM (systemMomentum()'s, from the tree's spatial inertias): the
  // mass and its first moment, the spatial momentum, and the rotational inertia.
  const size_t n = com.size();
  motions_.resize(n);
  SystemMomentum s;
  Vec3 first_moment = Vec3::Zero();
  Vec6 momentum = Vec6::Zero();
  Mat3 about_base = Mat3::Zero();
  for (size_t k = 0; k < n; ++k) {
    const double mass = model->links[k].mass;
    s.mass += mass;
    first_moment += mass * com[k];
    momentum.noalias() += inertia[k] * velocity[k];
    about_base += inertia[k].topLeftCorner<3, 3>();
    LinkMotion& b = motions_[k];
    b.com = base + com[k];
    b.angular_velocity = velocity[k].head<3>();
    b.velocity = velocity[k].tail<3>() + b.angular_velocity.cross(com[k]);
  }
  if (s.mass <= 0.0) return s;
  // About the common COM c: the same linear momentum, the moment less c x p, and the
  // inertia less that of the whole mass at c (parallel axes).
  const Vec3 c = first_moment / s.mass;
  s.com = base + c;
  s.linear = momentum.tail<3>();
  s.body_linear = s.linear;
  s.angular = momentum.head<3>() - c.cross(s.linear);
  s.inertia = about_base - s.mass * (c.squaredNorm() * Mat3::Identity() - c * c.transpose());
  if (added_mass_density_ <= 0.0) return s;
  for (AeroBody& a : aero) {
    if (!a.has_added_mass) continue;
    const LinkMotion& b = motions_[a.link];
    Vec6 v;
    v << b.angular_velocity, b.velocity;
    addFluidMomentum(s, turnedAddedMass(a, tree.rotations()[a.link]), b.com, v);
  }
  return s;
}

void CreatureBody::beginStep(double added_mass_density) {
  const int links = mb->getNumLinks();
  start_joint_velocity_.resize(static_cast<size_t>(links));
  for (int l = 0; l < links; ++l) start_joint_velocity_[l] = jointVel(*mb, l);
  start_base_omega_ = fromBt(mb->getBaseOmega());
  start_base_velocity_ = fromBt(mb->getBaseVel());
  external_force_.setZero();
  external_moment_.setZero();
  drag_impulse_.setZero();
  const bool carried = carried_valid_ && carried_density_ == added_mass_density;
  carried_valid_ = false;
  added_mass_density_ = added_mass_density;
  if (model->fixed_base) return;
  start_ = carried ? carried_ : measureMomentum();
}

void CreatureBody::forgetMomentum() { carried_valid_ = false; }

void CreatureBody::addExternal(const Vec3& com, const Wrench& wrench) {
  external_force_ += wrench.force;
  external_moment_ += (com - fromBt(frames.local_origin[0])).cross(wrench.force) + wrench.torque;
}

void CreatureBody::endStep(const Vec3& gravity, double dt) {
  last_step = dt;
  carried_valid_ = false;
  // A saturated servo pushed with its bound all step: a constant torque, under which (with
  // the air and gravity) its joint moves by the trapezoid of its velocities, where Bullet's
  // semi-implicit step takes the end velocity. A servo that holds its target velocity
  // moves at the end velocity all step, as Bullet has it. Not in contact: impulses there.
  // Nor near a joint's stop, where the limit's impulse may have acted.
  if (!scene->hasContacts()) {
    for (size_t k = 1; k < solution.saturated.size(); ++k) {
      if (!solution.saturated[k]) continue;
      const int l = static_cast<int>(k) - 1;
      const double v0 = start_joint_velocity_[l], v1 = jointVel(*mb, l);
      const double q = mb->getJointPos(l);
      const JointModel& j = model->joints[model->links[k].parent_joint];
      const double reach = dt * std::max(std::abs(v0), std::abs(v1));
      if (j.limited && (q - j.lower <= reach || j.upper - q <= reach)) continue;
      mb->setJointPos(l, q - 0.5 * dt * (v1 - v0));
    }
  }
  const Vec3 origin = fromBt(frames.local_origin[0]);  // of the start of the step
  if (model->fixed_base || scene->hasContacts() || start_.mass <= 0.0) {
    // Bullet's step placed the links (and the joints moved above have their caches from
    // setJointPos); after a lean step, the same sums without writing the multibody.
    if (scene->world().leanStepped()) {
      multiBodyFrames(*mb, frames.world_to_local, frames.local_origin);
    } else {
      mb->forwardKinematics(frames.world_to_local, frames.local_origin);
    }
    mb->compTreeLinkVelocities(frames.omega.data(), frames.vel.data());
    return;
  }
  // What the momentum must be: the start plus the external impulses (gravity has no moment
  // about the centre of mass).
  const Vec3 linear =
      start_.linear + dt * (start_.mass * gravity + external_force_) + drag_impulse_.tail<3>();
  Vec6 air;
  air << external_moment_, external_force_;
  const Vec3 angular = start_.angular + dt * momentAbout(air, origin, start_.com) +
                       momentAbout(drag_impulse_, origin, start_.com);
  const SystemMomentum now = measureMomentum();
  const RigidCorrection c = momentumCorrection(now, linear, angular);
  // The centre of mass moves with the bodies' new momentum.
  const Vec3 body_velocity = now.body_linear / now.mass + c.velocity;
  const Vec3 shift = start_.com + dt * body_velocity - now.com;
  // The same rigid motion on the multibody's base and on the frames, which are those of the
  // measure (its tree's rotations are the sums of forwardKinematics) plus the correction.
  const Vec3 base = fromBt(mb->getBasePos());
  mb->setBasePos(toBt(base + shift));
  mb->setBaseOmega(mb->getBaseOmega() + toBt(c.angular_velocity));
  mb->setBaseVel(mb->getBaseVel() + toBt(c.velocity + c.angular_velocity.cross(base - now.com)));
  const TreeDynamics& tree = scene->world().tree();
  const int bodies = static_cast<int>(motions_.size());
  frames.world_to_local.resize(bodies);
  frames.local_origin.resize(bodies);
  for (int k = 0; k < bodies; ++k) {
    const LinkMotion& b = motions_[k];
    // Velocities into the link's frame, as Bullet keeps them.
    const Mat3& to_world = tree.rotations()[k];
    const Vec3 w = b.angular_velocity + c.angular_velocity;
    const Vec3 v = b.velocity + c.velocity + c.angular_velocity.cross(b.com - now.com);
    frames.world_to_local[k] = tree.worldToLocal()[k];
    frames.local_origin[k] = toBt(Vec3(b.com + shift));
    frames.omega[k] = toBt(Vec3(to_world.transpose() * w));
    frames.vel[k] = toBt(Vec3(to_world.transpose() * v));
  }
  // The momentum is now the target, about the shifted centre of mass: the next step starts
  // from it instead of measuring it again.
  carried_.mass = now.mass;
  carried_.com = now.com + shift;
  carried_.linear = linear;
  carried_.angular = angular - shift.cross(linear);
  carried_valid_ = true;
  carried_density_ = added_mass_density_;
}

}  // namespace flapsim
