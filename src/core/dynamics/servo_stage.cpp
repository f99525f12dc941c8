#include "dynamics/servo_stage.h"

#include <algorithm>
#include <cmath>

#include "dynamics/bullet_body.h"
#include "fluid/creature_fluid.h"

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

bool implicitJoint(const CreatureModel& m, const JointModel& j, double dt) {
  return j.damping > dampingLimit(m, j, dt) || j.stiffness > stiffnessLimit(m, j, dt);
}

ServoStage::ServoStage(const CreatureModel& m, const WorldParams& params) : model_(&m) {
  max_effort_.assign(m.joints.size(), 0.0);
  damping_.assign(m.joints.size(), 0.0);
  stiffness_.assign(m.joints.size(), 0.0);
  implicit_.assign(m.joints.size(), 0);
  for (size_t ji = 0; ji < m.joints.size(); ++ji) {
    const JointModel& j = m.joints[ji];
    if (!j.movable()) continue;
    max_effort_[ji] = j.effort > 0.0 ? j.effort : params.default_wing_effort;
    damping_[ji] = j.damping;
    stiffness_[ji] = j.stiffness;
    implicit_[ji] = implicitJoint(m, j, params.step_size);
    any_implicit_ = any_implicit_ || implicit_[ji];
  }
  const size_t links = m.links.size();
  target_.assign(links, 0.0);
  demands_.assign(links, ServoDemand());
  links_.resize(links);
  for (size_t k = 0; k < links; ++k) {
    const LinkModel& l = m.links[k];
    ServoLink& s = links_[k];
    s.mass = l.mass;
    if (k == 0) continue;
    const JointModel& j = m.joints[l.parent_joint];
    s.parent = j.parent_link;
    s.joint = j.type == JointType::kFixed       ? ServoJointType::kFixed
              : j.type == JointType::kPrismatic ? ServoJointType::kPrismatic
                                                : ServoJointType::kRevolute;
  }
}

void ServoStage::demand(int link, double target, double effort, double dt) {
  demand(link, target, flatTorqueBounds(effort), dt);
}

void ServoStage::demand(int link, double target, const TorqueBounds& bounds, double dt) {
  ServoDemand& d = demands_[link];
  d.active = true;
  d.max_impulse = bounds.positive * dt;
  d.max_negative_impulse = bounds.negative * dt;
  target_[link] = target;
}

void ServoStage::begin(const btMultiBody& mb, double dt) {
  step_ = dt;
  const int links = mb.getNumLinks();
  start_joint_velocity_.resize(static_cast<size_t>(links));
  for (int l = 0; l < links; ++l) start_joint_velocity_[l] = jointVel(mb, l);
  start_base_omega_ = fromBt(mb.getBaseOmega());
  start_base_velocity_ = fromBt(mb.getBaseVel());
}

void ServoStage::forget() {
  solution_ = ServoSolution();
  last_step_ = 1.0;
}

void ServoStage::updateLinks(const LinkFrames& frames) {
  const CreatureModel& m = *model_;
  const btVector3 origin = frames.com(0);  // the root's COM
  for (size_t k = 0; k < links_.size(); ++k) {
    const LinkModel& l = m.links[k];
    ServoLink& s = links_[k];
    const btMatrix3x3 rot(frames.worldToLink(static_cast<int>(k)).inverse());
    const btMatrix3x3 inertia = rot.scaled(toBt(l.inertia)) * rot.transpose();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) s.inertia(r, c) = inertia[r][c];
    }
    s.com = fromBt(frames.com(static_cast<int>(k)) - origin);
    if (k > 0) {
      const JointModel& j = m.joints[l.parent_joint];
      s.axis = fromBt(rot * toBt(j.axis));
      s.anchor = fromBt(frames.com(static_cast<int>(k)) - rot * toBt(l.com) - origin);
    }
  }
}

void ServoStage::velocityChanges(const btMultiBody& mb, const ServoTree& tree) {
  const size_t n = links_.size();
  change_of_link_.resize(n);
  if (tree.bias) {
    // The solve's velocity changes hold the step's velocity products, which the joints'
    // velocities do not: less their sums along the tree, they are the joints'. The root's
    // change is its COM's, as measured from begin(): the spatial one plus step x omega x v.
    change_of_link_[0] << Vec3::Zero(), base_bias_;
    for (size_t k = 1; k < n; ++k) {
      change_of_link_[k] = change_of_link_[links_[k].parent];
      if (links_[k].joint != ServoJointType::kFixed) {
        change_of_link_[k] -= tree.step * (*tree.coriolis)[k];
      }
    }
    return;
  }
  // The root's [angular; linear of its COM], which is the point the spatial velocities are
  // taken at.
  change_of_link_[0] << fromBt(mb.getBaseOmega()) - start_base_omega_,
      fromBt(mb.getBaseVel()) - start_base_velocity_;
  for (size_t k = 1; k < n; ++k) {
    const ServoLink& l = links_[k];
    change_of_link_[k] = change_of_link_[l.parent];
    if (l.joint == ServoJointType::kFixed) continue;
    const int link = static_cast<int>(k) - 1;
    const double dq = jointVel(mb, link) - start_joint_velocity_[link];
    change_of_link_[k] += (tree.subspace ? (*tree.subspace)[k] : motionSubspace(l)) * dq;
  }
}

Vec6 ServoStage::solveWithFluid(const btMultiBody& mb, const LinkFrames& frames,
                                const ServoTree& tree, const CreatureFluid& fluid) {
  velocityChanges(mb, tree);
  const ServoLoads& loads = fluid_.loads(fluid.bodies(), frames, links_.size(), change_of_link_);
  solver_.solve(links_, model_->fixed_base, demands_, loads, tree, solution_);
  return fluid_.dragImpulses(fluid.bodies(), solution_);
}

Vec6 ServoStage::solve(btMultiBody& mb, const LinkFrames& frames, TreeDynamics* lean,
                       const CreatureFluid& fluid) {
  bool any = false;
  for (size_t k = 1; k < demands_.size(); ++k) {
    if (!demands_[k].active) continue;
    demands_[k].velocity_change = target_[k] - jointVel(mb, static_cast<int>(k) - 1);
    any = true;
  }
  if (any_implicit_) setImplicitSprings(mb);
  fluid_.clear();
  if (!any && !fluid.active() && !any_implicit_) {
    solution_.impulse.assign(demands_.size(), 0.0);
    solution_.saturated.assign(demands_.size(), false);
    return Vec6::Zero();
  }
  // A lean step has the links' inertias and joint subspaces already (same frame and origin).
  ServoTree tree;
  const bool update = lean && lean->velocitiesPending();
  if (lean) {
    tree.inertia = &lean->bodyInertias();
    tree.subspace = &lean->jointAxes();
  } else {
    updateLinks(frames);
  }
  if (update) {
    base_bias_ = lean->baseLinearBias();
    tree.bias = &lean->biasForces();
    tree.coriolis = &lean->coriolis();
    tree.joint_torque = &lean->jointTorques();
    tree.step = lean->step();
  }
  Vec6 drag_impulse = Vec6::Zero();
  if (fluid.active()) {
    drag_impulse = solveWithFluid(mb, frames, tree, fluid);
  } else {
    solver_.solve(links_, model_->fixed_base, demands_, ServoLoads(), tree, solution_);
  }
  addVelocityChange(mb, update);
  if (update) lean->velocitiesUpdated();
  return drag_impulse;
}

void ServoStage::setImplicitSprings(const btMultiBody& mb) {
  for (size_t k = 1; k < demands_.size(); ++k) {
    ServoDemand& d = demands_[k];
    const int ji = model_->links[k].parent_joint;
    if (!implicit_[ji]) continue;
    // -k (q + dt v1 - reference) - c v1 with v1 = v + dq, v the velocity the solve's changes
    // are from (Bullet's after this step's forces; the start's when the solve takes the
    // velocity update too) and q the step's start.
    const int link = static_cast<int>(k) - 1;
    const double q = mb.getJointPos(link) - model_->joints[ji].reference;
    const double rate = damping_[ji] + step_ * stiffness_[ji];
    d.spring_impulse = -step_ * (stiffness_[ji] * q + rate * jointVel(mb, link));
    d.spring_damping = step_ * rate;
  }
}

void ServoStage::addVelocityChange(btMultiBody& mb, bool update) const {
  for (size_t k = 1; k < demands_.size(); ++k) {
    if (links_[k].joint == ServoJointType::kFixed) continue;
    const int link = static_cast<int>(k) - 1;
    mb.setJointVel(link, jointVel(mb, link) + solution_.velocity_change[k]);
  }
  if (!model_->fixed_base) {
    const Vec6& dv = solution_.root_velocity_change;
    mb.setBaseOmega(mb.getBaseOmega() + toBt(Vec3(dv.head<3>())));
    Vec3 linear = dv.tail<3>();
    if (update) linear += base_bias_;  // the fused update's velocity products (solve())
    mb.setBaseVel(mb.getBaseVel() + toBt(linear));
  }
}

void ServoStage::integrateSaturated(btMultiBody& mb, bool contacts, double dt) {
  last_step_ = dt;
  if (contacts) return;
  for (size_t k = 1; k < solution_.saturated.size(); ++k) {
    if (!solution_.saturated[k]) continue;
    const int l = static_cast<int>(k) - 1;
    const double v0 = start_joint_velocity_[l], v1 = jointVel(mb, l);
    const double q = mb.getJointPos(l);
    const JointModel& j = model_->joints[model_->links[k].parent_joint];
    const double reach = dt * std::max(std::abs(v0), std::abs(v1));
    if (j.limited && (q - j.lower <= reach || j.upper - q <= reach)) continue;
    mb.setJointPos(l, q - 0.5 * dt * (v1 - v0));
  }
}

}  // namespace flapsim
