// Joint velocity servos on a kinematic tree, solved exactly in O(links) per pass.
//
// Each driven joint gets the impulse that brings its velocity to the target by the end of
// the step, unless that impulse exceeds the joint's bound (effort x step), in which case
// it pushes with the bound. All servos are solved together, so a servo on one joint sees
// the motion the others cause (a left and a right wing stay mirror images), and the
// impulses are internal: the tree's momentum is conserved.
//
// This is the articulated-body algorithm in its hybrid-dynamics form (Featherstone,
// "Rigid Body Dynamics Algorithms", ch. 9) at impulse level: a driven joint has a
// prescribed velocity change and contributes its whole subtree's inertia to its parent; a
// passive or saturated joint has a known impulse. Saturation is found by an active-set
// loop (here); each pass costs O(links) (dynamics/hybrid_sweep.h). Pure functions of the
// tree at one instant: no Bullet.
#pragma once

#include <vector>

#include "dynamics/hybrid_sweep.h"
#include "dynamics/spatial.h"

namespace flapsim {

enum class ServoJointType { kFixed, kRevolute, kPrismatic };

/// One link of a tree at an instant; every vector is in one common frame. A parent comes
/// before its children; link 0 is the root.
struct ServoLink {
  int parent = -1;  // -1 for the root
  double mass = 0.0;
  Vec3 com = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();                    // about the COM, common-frame axes
  ServoJointType joint = ServoJointType::kFixed;  // the joint to the parent
  Vec3 axis = Vec3::UnitZ();                      // unit
  Vec3 anchor = Vec3::Zero();                     // a point on a revolute joint's axis
};

/// What one joint's servo asks for in this step.
struct ServoDemand {
  bool active = false;           // false: passive, no impulse
  double velocity_change = 0.0;  // wanted change of the joint velocity
  double max_impulse = 0.0;      // bound on |impulse| (N m s or N s), >= 0
  /// A different bound on -impulse (a motor's torque-speed line makes the bounds of driving
  /// and braking differ), >= 0; < 0: max_impulse bounds both directions.
  double max_negative_impulse = -1.0;
  /// The joint's spring and damper treated implicitly (ServoStage::solve): they add
  /// spring_impulse - spring_damping x (the joint's velocity change) to its impulse, with
  /// spring_damping >= 0, whether the joint is free (passive, or its servo pushing with its
  /// bound) or held at its target (the servo's impulse is then less by it). Not part of the
  /// solution's impulse, which is the servo's alone.
  double spring_impulse = 0.0;
  double spring_damping = 0.0;

  /// The bounds: -lower() <= impulse <= upper().
  double upper() const { return max_impulse; }
  double lower() const { return max_negative_impulse >= 0.0 ? max_negative_impulse : max_impulse; }
  /// Whether the servo can push at all.
  bool drives() const { return active && (upper() > 0.0 || lower() > 0.0); }
};

/// Optional per-link terms of a solve, each in the common frame about its origin (empty
/// vectors: none). `extra_inertia` adds to a link's spatial inertia (the fluid's added mass
/// and its linearised drag times the step, treated implicitly: symmetric, positive
/// semi-definite); `impulse` is a known spatial impulse [moment about the origin; force]
/// applied to the link in this step. `links`, if not empty, lists (each once) the only links
/// whose entries are read: the others' loads are zero, whatever their entries hold.
struct ServoLoads {
  std::vector<Mat6, Eigen::aligned_allocator<Mat6>> extra_inertia;
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> impulse;
  std::vector<int> links;
};

/// Per link, about the frame origin: its spatial inertia and its joint's motion subspace, for
/// a caller that has them already (JointServoSolver::solve).
struct ServoTree {
  const std::vector<Mat6, Eigen::aligned_allocator<Mat6>>* inertia = nullptr;
  const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>* subspace = nullptr;
  /// Optional (with `inertia` and `subspace`), one per link: the tree's velocity update over
  /// `step` solved with the servos (one pass over the tree instead of an articulated-body
  /// pass and then the servos'). Per link, its bias force (velocity products less applied
  /// forces), its joint's velocity-product acceleration and its joint's torque (0 for the
  /// root), each acting over `step`: the velocity changes and the prescribed ones are then
  /// from the velocities these were taken at, and the driven joints' impulses are the servos'
  /// alone (beyond step x joint torque).
  const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>* bias = nullptr;
  const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>* coriolis = nullptr;
  const std::vector<double>* joint_torque = nullptr;
  double step = 0.0;
};

struct ServoSolution {
  std::vector<double> impulse;               // per link: along its joint (0 if fixed or root)
  std::vector<double> velocity_change;       // per link: of its joint velocity
  Vec6 root_velocity_change = Vec6::Zero();  // [angular; linear at the frame origin]
  /// Per link: the change of its spatial velocity [angular; linear at the frame origin].
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> link_velocity_change;
  std::vector<bool> saturated;  // per link: pushing with its bound
  int passes = 0;               // active-set passes (each O(links))
};

/// The joint's motion subspace: the spatial velocity of a unit joint rate.
Vec6 motionSubspace(const ServoLink& link);
class JointServoSolver {
 public:
  /// Solves the servos of `demands` (one per link; the root's is ignored). `fixed_root`:
  /// the root cannot move. Throws std::invalid_argument unless there is one demand per
  /// link. Keeps its scratch between calls: no allocation once warm.
  void solve(const std::vector<ServoLink>& links, bool fixed_root,
             const std::vector<ServoDemand>& demands, ServoSolution& out);
  /// The same with extra inertias and known impulses on the links (see ServoLoads); throws
  /// std::invalid_argument if a non-empty vector of `loads` has not one entry per link.
  void solve(const std::vector<ServoLink>& links, bool fixed_root,
             const std::vector<ServoDemand>& demands, const ServoLoads& loads, ServoSolution& out);
  /// The same with the links' inertias and subspaces given (one per link) instead of computed
  /// from `links`, which then give only the tree (parents, joint types).
  void solve(const std::vector<ServoLink>& links, bool fixed_root,
             const std::vector<ServoDemand>& demands, const ServoLoads& loads,
             const ServoTree& tree, ServoSolution& out);

 private:
  // A prescribed joint whose impulse is beyond a bound pushes with that bound instead: made
  // free at it; whether it was.
  bool saturate(size_t k, const ServoDemand& d, double impulse);
  // Throws std::invalid_argument unless every vector has one entry per link.
  void checkArguments(const std::vector<ServoLink>& links, const std::vector<ServoDemand>& demands,
                      const ServoLoads& loads, const ServoTree& tree) const;
  // Starts the solution and every joint's status (warm from the last solve); returns how many
  // joints are driven.
  int prepare(const std::vector<ServoLink>& links, const std::vector<ServoDemand>& demands,
              ServoSolution& out);
  // Passes until no servo changes between driven and pushing with its bound.
  void settleActiveSet(const std::vector<ServoLink>& links, bool fixed_root,
                       const std::vector<ServoDemand>& demands, const ServoLoads& loads, int driven,
                       ServoSolution& out);

  HybridSweep sweep_;              // the tree of a solve, its joints' statuses and its passes
  std::vector<signed char> side_;  // of a saturated joint: +1 at its upper bound, -1 at its lower
  // Per link: the sign of its bound if it was saturated in the last solve, else 0. The
  // active set starts from it: the solution is unique, and saturated servos mostly stay so
  // from one step to the next, which then takes one pass instead of two.
  std::vector<signed char> warm_;
};

}  // namespace flapsim
