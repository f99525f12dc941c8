// The fluid's implicit part in a creature's servo solve (dynamics/servo_stage.h): the aero
// bodies' added mass and linearised drag as extra inertias of the solve's tree, with the
// impulses that keep the velocity changes it solves for measured from the step's start, and
// after the solve the implicit drag's impulse on each aero body. Private to flapsim_core.
#pragma once

#include <vector>

#include "dynamics/joint_servo.h"
#include "dynamics/spatial.h"

namespace flapsim {

class LinkFrames;
struct AeroBody;

class ImplicitFluidLoads {
 public:
  /// (M + A) (v1 - v0) = M (vb - v0) + servo impulses, with A the fluid's implicit part and vb
  /// Bullet's velocities after this step's forces: solved for v1 - vb, it is the tree with
  /// inertia M + A under the impulses -A (vb - v0) on the aero bodies. The loads of a tree of
  /// `links` links, per aero body with implicit drag or added mass (ServoLoads::links), whose
  /// links' spatial velocities changed by `change_of_link` (vb - v0, about the root COM of the
  /// step's start) since the step began. Valid until the next call.
  const ServoLoads& loads(const std::vector<AeroBody>& aero, const LinkFrames& frames, size_t links,
                          const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>& change_of_link);
  /// After the solve of those loads (`solution`): each aero body's implicit drag impulse over
  /// the step, -step D (v1 - v0); returns their sum [moment about the root COM; force].
  Vec6 dragImpulses(const std::vector<AeroBody>& aero, const ServoSolution& solution);
  /// The implicit drag's impulse on aero body i (CreatureFluid's order) of the last solve
  /// [moment about the root COM of the step's start; force], world axes (zero without one).
  Vec6 dragImpulse(size_t i) const {
    return i < drag_impulse_.size() ? drag_impulse_[i] : Vec6::Zero();
  }
  /// No implicit drag in this step (a solve without the fluid).
  void clear() { drag_impulse_.clear(); }

 private:
  // Scratch, kept between steps: no allocation once warm.
  ServoLoads loads_;
  // Per aero body: its drag matrix about the root COM, and Bullet's change of its spatial
  // velocity in this step.
  std::vector<Mat6, Eigen::aligned_allocator<Mat6>> drag_;
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> change_;
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> drag_impulse_;  // per aero body
};

}  // namespace flapsim
