// The servo stage of a creature's step: its joint servos (wing motors, velocity targets,
// feathering, Coulomb friction) and the fluid's implicit part (added mass, linearised drag),
// solved together as one impulse problem (dynamics/joint_servo.h) between Bullet's
// unconstrained velocity update (gravity, air, damping) and its constraint solve (limits,
// contacts), where Bullet's own joint motors act (the stages "velocities", "servos" and
// "constraints" of world/creature_step.h). Private to flapsim_core.
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <vector>

#include "dynamics/implicit_fluid.h"
#include "dynamics/joint_servo.h"
#include "dynamics/motor.h"
#include "dynamics/spatial.h"
#include "dynamics/tree_dynamics.h"
#include "flapsim/creature_model.h"
#include "flapsim/world.h"

namespace flapsim {

class LinkFrames;
class CreatureFluid;

class ServoStage {
 public:
  // The servos of creature `m` (kept by pointer: it must outlive the stage), with its joints'
  // effort bounds, damping and stiffness, the stiff ones implicit at the world's step.
  ServoStage(const CreatureModel& m, const WorldParams& params);

  // Per model joint: the servo's torque bound, the passive damping and the spring stiffness,
  // and whether the two act implicitly, in the solve (stiffer than an explicit step keeps
  // stable, see dampingLimit()), rather than as explicit torques.
  double maxEffort(size_t joint) const { return max_effort_[joint]; }
  double damping(size_t joint) const { return damping_[joint]; }
  double stiffness(size_t joint) const { return stiffness_[joint]; }
  bool implicitSpring(size_t joint) const { return implicit_[joint] != 0; }

  // The actuation stage's demands for this step, per link (the servo of the joint to its
  // parent): none, or a target velocity at the end of the step under a torque bound.
  void release(int link) { demands_[link].active = false; }
  void demand(int link, double target, double effort, double dt);
  // The same under a motor's bounds, which differ in the two directions (dynamics/motor.h).
  void demand(int link, double target, const TorqueBounds& bounds, double dt);

  // The start of a (sub)step of `dt`: the velocities the fluid's implicit part and the
  // saturated servos' correction are measured from.
  void begin(const btMultiBody& mb, double dt);
  // Between ServoWorld::beginStep() and constrain(), once the velocities hold gravity, air
  // and damping: solves every servo and the fluid's implicit part together and adds the
  // velocity change they cause (frames of the start of the step; `lean`: the lean step's
  // tree, ServoWorld::leanTree(), if this is one). On a
  // lean step whose velocity update is still to come (TreeDynamics::velocitiesPending()) the
  // same solve takes the update as well (ServoTree::bias), unless no servo acts and the
  // fluid has no implicit part. Returns the implicit drag's impulse over the step [moment
  // about the root COM; force] (the added mass is part of the momentum itself).
  Vec6 solve(btMultiBody& mb, const LinkFrames& frames, TreeDynamics* lean,
             const CreatureFluid& fluid);
  // After Bullet's step of `dt`: a saturated servo pushed with its bound all step, a constant
  // torque, under which (with the air and gravity) its joint moves by the trapezoid of its
  // velocities, where Bullet's semi-implicit step takes the end velocity. Not in contact
  // (impulses there), nor near a joint's stop, where the limit's impulse may have acted.
  void integrateSaturated(btMultiBody& mb, bool contacts, double dt);
  // After a state set from outside a step: no servo history.
  void forget();

  // Of the last solve: impulses all zero if no servo acted.
  const ServoSolution& solution() const { return solution_; }
  // The velocity of Bullet link `link`'s joint at begin(): the (sub)step's start.
  double startVelocity(int link) const { return start_joint_velocity_[link]; }
  // The implicit drag's impulse on aero body i (CreatureFluid's order) in the last solve
  // [moment about the root COM of the step's start; force], world axes (zero without one).
  Vec6 dragImpulse(size_t i) const { return fluid_.dragImpulse(i); }
  bool saturated(size_t link) const {
    return link < solution_.saturated.size() && solution_.saturated[link];
  }
  // The torque (force) the servo of the joint to `link` applied in the last (sub)step.
  double effort(size_t link) const {
    return link < solution_.impulse.size() ? solution_.impulse[link] / last_step_ : 0.0;
  }

 private:
  // Inertias, COMs, axes and anchors of the links in the world frame, relative to the
  // root's COM.
  void updateLinks(const LinkFrames& frames);
  // Per link, the change of its spatial velocity [angular; linear at the root COM of the
  // step's start] since begin(), from the joints' (the motion subspaces of `tree`, else of
  // links_) into change_of_link_. With the velocity update in the solve (ServoTree::bias),
  // no change yet, but the solve's changes hold the step's velocity products, which are
  // taken off here: then minus their sums from the root.
  void velocityChanges(const btMultiBody& mb, const ServoTree& tree);
  // The servos with the fluid's implicit part (dynamics/implicit_fluid.h); returns the implicit
  // drag's impulse.
  Vec6 solveWithFluid(const btMultiBody& mb, const LinkFrames& frames, const ServoTree& tree,
                      const CreatureFluid& fluid);
  // Each implicit spring's impulse terms in its link's demand (ServoDemand::spring_impulse),
  // from the joint's position and velocity when the solve starts.
  void setImplicitSprings(const btMultiBody& mb);
  // The velocity change of the last solve added to the multibody (`update`: a solve with the
  // velocity update, whose root COM also gains base_bias_).
  void addVelocityChange(btMultiBody& mb, bool update) const;

  const CreatureModel* model_;
  std::vector<double> max_effort_, damping_, stiffness_;  // per model joint
  std::vector<char> implicit_;                            // per model joint
  bool any_implicit_ = false;
  double step_ = 0.0;                 // of this (sub)step
  std::vector<double> target_;        // per link: velocity wanted
  std::vector<ServoDemand> demands_;  // per link
  std::vector<ServoLink> links_;
  JointServoSolver solver_;
  ServoSolution solution_;
  double last_step_ = 1.0;  // s: the last (sub)step taken, for efforts from impulses
  std::vector<double> start_joint_velocity_;  // per Bullet link
  Vec3 start_base_omega_ = Vec3::Zero();      // world frame
  Vec3 start_base_velocity_ = Vec3::Zero();   // of the base's COM
  // In a solve with the velocity update, what the base COM's velocity gains over the step
  // beyond the spatial change (TreeDynamics::baseLinearBias()).
  Vec3 base_bias_ = Vec3::Zero();
  // Scratch, kept between steps: no allocation once warm.
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> change_of_link_;
  ImplicitFluidLoads fluid_;  // the fluid's loads of the solve and its drag impulses
};

// Joint damping is an explicit torque -d qdot, stable while d dt stays well under the joint's
// inertia, and a <spring> an explicit torque -k (q - reference), stable while the child link's
// own oscillation sqrt(k / I) dt stays below 2. A joint whose damping is more than a quarter of
// the child link's own inertia about the axis per step, or whose stiffness is more than a
// quarter of it per step squared, has both treated implicitly instead, in the servo solve
// (backward Euler: -k (q0 + dt v1 - reference) - d v1, unconditionally stable; its motion
// faster than the step is damped out).
double dampingLimit(const CreatureModel& m, const JointModel& j, double dt);
double stiffnessLimit(const CreatureModel& m, const JointModel& j, double dt);
// Whether joint `j`'s damping or stiffness is beyond those limits at steps of `dt` (both then
// act implicitly).
bool implicitJoint(const CreatureModel& m, const JointModel& j, double dt);

}  // namespace flapsim
