// The inner pass of JointServoSolver (dynamics/joint_servo.h): the articulated-body algorithm
// in its hybrid-dynamics form at impulse level (Featherstone, "Rigid Body Dynamics
// Algorithms", ch. 9) over a tree whose joints' statuses are known. Leaves to root, a driven
// joint's prescribed velocity change carries its whole subtree's inertia to its parent and a
// free joint's known impulse its articulated inertia; root to leaves, the velocity changes
// follow, and the impulses the prescribed joints take. Which joints are prescribed (the active
// set) is the solver's. Private to flapsim_core.
#pragma once

#include <vector>

#include "dynamics/spatial.h"

namespace flapsim {

struct ServoLink;
struct ServoDemand;
struct ServoLoads;
struct ServoTree;
struct ServoSolution;

/// A joint in a pass: fixed (no joint velocity), free under a known impulse (a passive joint,
/// or a servo pushing with its bound), or prescribed its velocity change (a driven servo).
enum class JointStatus { kFixed, kFree, kPrescribed };

class HybridSweep {
 public:
  /// Takes the tree of a solve (see JointServoSolver::solve): per link its spatial inertia,
  /// computed from `links` or given by `tree`, with the extra inertias of `loads`, its joint's
  /// motion subspace, and with a velocity update (ServoTree::bias) the step's terms; `tree`'s
  /// inertias and subspaces are read in place by the passes that follow. `links` has at least
  /// one link. Keeps its scratch between solves: no allocation once warm.
  void load(const std::vector<ServoLink>& links, const ServoLoads& loads, const ServoTree& tree);
  /// Per link: its joint's status in the next passes and, if free, its known impulse. load()
  /// sizes them, every known impulse zero; the solver then sets every joint's status.
  JointStatus status(size_t k) const { return status_[k]; }
  void setStatus(size_t k, JointStatus status) { status_[k] = status; }
  void setFree(size_t k, double impulse) {
    status_[k] = JointStatus::kFree;
    tau_[k] = impulse;
  }
  /// One pass over the tree last loaded under the joints' statuses, with the known impulses of
  /// `loads`: writes out's velocity changes (joints, links, root) and its impulses (the
  /// prescribed joints', the free ones' known impulses), and counts the pass.
  void run(const std::vector<ServoLink>& links, bool fixed_root,
           const std::vector<ServoDemand>& demands, const ServoLoads& loads, ServoSolution& out);

 private:
  // Leaves to root: articulated inertias and bias impulses.
  void inwardPass(const std::vector<ServoLink>& links, const std::vector<ServoDemand>& demands);
  // Root to leaves: velocity changes and the prescribed joints' impulses.
  void outwardPass(const std::vector<ServoLink>& links, bool fixed_root,
                   const std::vector<ServoDemand>& demands, ServoSolution& out);

  std::vector<JointStatus> status_;
  std::vector<double> tau_;  // known impulse of a free joint

  std::vector<Mat6, Eigen::aligned_allocator<Mat6>> body_inertia_, articulated_;
  // The links' spatial inertias in this solve: body_inertia_ or the caller's.
  const std::vector<Mat6, Eigen::aligned_allocator<Mat6>>* inertia_ = &body_inertia_;
  bool listed_extra_ = false;  // a pass adds the extra inertias of loads.links itself
  // The joints' motion subspaces in this solve: body_subspace_ or the caller's.
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> body_subspace_;
  const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>* subspace_ = &body_subspace_;
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> bias_, u_vec_, dv_;
  std::vector<double> d_, u_;
  // A solve with the velocity update (ServoTree::bias): per link, step x its bias force and
  // step x its joint's velocity-product acceleration; step x joint torque.
  bool update_ = false;
  std::vector<Vec6, Eigen::aligned_allocator<Vec6>> step_bias_, step_coriolis_;
  std::vector<double> step_torque_;
};

}  // namespace flapsim
