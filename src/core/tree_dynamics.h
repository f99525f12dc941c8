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

#include "flapsim/joint_servo.h"

namespace flapsim {

class TreeDynamics {
 public:
  // Whether velocityStep() handles `mb`: revolute, prismatic and fixed joints, no link
  // damping, the gyroscopic term on, no joint feedback (as flapsim builds its multibodies).
  static bool handles(const btMultiBody& mb);

  // The joint accelerations and the base's (angular, and linear of its centre of mass, world
  // frame) under the multibody's applied forces, torques and joint torques, in Bullet's
  // velocity order (6 base values, then one per joint dof).
  const std::vector<double>& accelerations(const btMultiBody& mb);

  // Of the last accelerations(), per body (0: the base, k + 1: link k), about the base's COM,
  // world axes: spatial inertias and joint motion subspaces (zero for the base and fixed
  // joints).
  const std::vector<Mat6, Eigen::aligned_allocator<Mat6>>& bodyInertias() const { return body_; }
  const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>& jointAxes() const { return axis_; }

  // What Bullet's step does with them: velocities += dt * accelerations (clamped to the
  // multibody's maximum coordinate velocity).
  void velocityStep(btMultiBody& mb, double dt);

 private:
  void linkFrames(const btMultiBody& mb);
  void velocitiesAndBias(const btMultiBody& mb);
  void inwardPass(const btMultiBody& mb);
  void outwardPass(const btMultiBody& mb);

  // Per body (0: the base, k + 1: link k), about the base's COM, world axes.
  std::vector<Quat, Eigen::aligned_allocator<Quat>> to_local_;  // world to body rotation
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
  std::vector<double> out_;  // Bullet's velocity order
};

}  // namespace flapsim
