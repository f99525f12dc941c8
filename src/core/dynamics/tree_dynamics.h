// The unconstrained velocity update of a btMultiBody (forces, gravity, gyroscopic and
// Coriolis terms) computed in the world frame, for lean steps. Private to flapsim_core.
//
// Bullet's computeAccelerationsArticulatedBodyAlgorithmMultiDof runs Featherstone's
// articulated-body algorithm in link frames with generic 3x3 and spatial helpers, and also
// fills the caches its constraint solver needs; it is a third of a contact-free step. Here
// the same algorithm (Featherstone, "Rigid Body Dynamics Algorithms", table 7.1) runs with
// every quantity about one point, the base's centre of mass, in world axes: no transforms
// between links, fixed-size Eigen arithmetic. The accelerations are the same up to rounding.
#pragma once

#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <vector>

#include "dynamics/joint_servo.h"

namespace flapsim {

class TreeDynamics {
 public:
  // Whether beginStep() and finishVelocityStep() handle `mb`: revolute, prismatic and fixed joints,
  // no link damping, the gyroscopic term on, no joint feedback (as flapsim builds its multibodies).
  static bool handles(const btMultiBody& mb);

  // The joint accelerations and the base's (angular, and linear of its centre of mass, world
  // frame) under the multibody's applied forces, torques and joint torques, in Bullet's
  // velocity order (6 base values, then one per joint dof).
  const std::vector<double>& accelerations(const btMultiBody& mb);

  // Brings the per-body frames below to the multibody's positions: recomputed only if what
  // they are made of (the base's rotation, Bullet's cached parent-to-link rotations and
  // offsets, the masses and inertias) changed since the last call. A step's momentum taken
  // after its positions then serves the next step's accelerations as well.
  void updateFrames(const btMultiBody& mb);
  // Of the last updateFrames(), per body (0: the base, k + 1: link k): its rotation (body to
  // world) and its COM minus the base's.
  const std::vector<Mat3, Eigen::aligned_allocator<Mat3>>& rotations() const { return rot_; }
  // The same rotations as quaternions, world to body, by btMultiBody::forwardKinematics'
  // arithmetic (the same bits as its frames).
  const btAlignedObjectArray<btQuaternion>& worldToLocal() const { return to_local_; }
  const std::vector<Vec3, Eigen::aligned_allocator<Vec3>>& coms() const { return com_; }
  // Every body's spatial velocity [angular; linear at the base's COM], world axes, at the
  // multibody's velocities and the frames of the last updateFrames().
  const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>& velocities(const btMultiBody& mb);

  // Of the last updateFrames() (which accelerations() calls), per body (0: the base, k + 1:
  // link k), about the base's COM, world axes: spatial inertias and joint motion subspaces
  // (zero for the base and fixed joints).
  const std::vector<Mat6, Eigen::aligned_allocator<Mat6>>& bodyInertias() const { return body_; }
  const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>& jointAxes() const { return axis_; }

  // What Bullet's step does with them, velocities += dt * accelerations (clamped to the
  // multibody's maximum coordinate velocity), in two halves, between which the servo stage
  // may take it over (the unconstrained update and the servos in one solve,
  // ServoTree::bias): beginStep() takes the frames, the velocities and the multibody's
  // applied forces, torques and joint torques (which may be cleared after it);
  // finishVelocityStep() does the rest unless velocitiesUpdated() was called in between.
  void beginStep(const btMultiBody& mb, double dt);
  void finishVelocityStep(btMultiBody& mb);
  bool velocitiesPending() const { return pending_; }
  void velocitiesUpdated() { pending_ = false; }
  // While velocitiesPending(), per body (about the base's COM, world axes): the bias force
  // (velocity products less the applied forces) and the velocity-product acceleration of
  // its joint, the joint torques (0 for the base and fixed joints), the step, and what the
  // base COM's velocity gains over the step beyond the spatial velocity change (omega x v,
  // times the step).
  const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>& biasForces() const { return bias_; }
  const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>& coriolis() const { return coriolis_; }
  const std::vector<double>& jointTorques() const { return torque_; }
  double step() const { return dt_; }
  Vec3 baseLinearBias() const;

 private:
  void linkFrames(const btMultiBody& mb);
  // Whether the frames' inputs are those of the last linkFrames(); records them if not.
  bool framesCurrent(const btMultiBody& mb);
  // Spatial velocities, velocity-product accelerations, bias forces and joint torques.
  void velocitiesAndBias(const btMultiBody& mb);
  void inwardPass(const btMultiBody& mb);
  void outwardPass(const btMultiBody& mb);

  // Per body (0: the base, k + 1: link k), about the base's COM, world axes.
  // World to body rotation, by multiBodyFrames()' arithmetic: the same bits as the frames.
  btAlignedObjectArray<btQuaternion> to_local_;
  std::vector<Mat3, Eigen::aligned_allocator<Mat3>> rot_;       // body to world
  std::vector<Vec3, Eigen::aligned_allocator<Vec3>> com_;       // body COM - base COM
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> axis_;      // joint's motion subspace
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> velocity_;  // spatial velocity
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> coriolis_;  // velocity-product accel.
  std::vector<Mat6, Eigen::aligned_allocator<Mat6>> body_;      // spatial inertia
  std::vector<Mat6, Eigen::aligned_allocator<Mat6>> inertia_;   // articulated inertia
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> bias_;      // articulated bias force
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> u_vec_;     // inertia x axis
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> accel_;     // spatial acceleration
  std::vector<double> inv_d_, u_;
  std::vector<double> torque_;  // joint torque
  double dt_ = 0.0;
  bool pending_ = false;
  std::vector<double> out_;  // Bullet's velocity order
  // The inputs of the frames (framesCurrent()), and scratch to gather them.
  const btMultiBody* framed_ = nullptr;
  std::vector<btScalar> frame_inputs_, inputs_;
};

}  // namespace flapsim
