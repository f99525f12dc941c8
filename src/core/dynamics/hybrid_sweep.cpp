#include "dynamics/hybrid_sweep.h"

#include <algorithm>
#include <vector>

#include "dynamics/joint_servo.h"

namespace flapsim {

void HybridSweep::load(const std::vector<ServoLink>& links, const ServoLoads& loads,
                       const ServoTree& tree) {
  const size_t n = links.size();
  const bool given = tree.inertia && tree.subspace;
  status_.resize(n);
  tau_.resize(n);
  std::fill(tau_.begin(), tau_.end(), 0.0);
  body_inertia_.resize(n);
  const bool extra = !loads.extra_inertia.empty();
  // Given inertias are read where they are, unless loads add to every link's.
  listed_extra_ = given && extra && !loads.links.empty();
  inertia_ = given && (!extra || listed_extra_) ? tree.inertia : &body_inertia_;
  articulated_.resize(n);
  bias_.resize(n);
  u_vec_.resize(n);
  dv_.resize(n);
  d_.resize(n);
  u_.resize(n);
  update_ = given && tree.bias;
  if (update_) {
    step_bias_.resize(n);
    step_coriolis_.resize(n);
    step_torque_.resize(n);
    for (size_t k = 0; k < n; ++k) {
      step_bias_[k] = tree.step * (*tree.bias)[k];
      step_coriolis_[k] = tree.step * (*tree.coriolis)[k];
      step_torque_[k] = tree.step * (*tree.joint_torque)[k];
    }
  }
  // Given subspaces are read where they are, as given inertias are; the own ones are the
  // tree's, with any extra inertias.
  subspace_ = given ? tree.subspace : &body_subspace_;
  if (!given) body_subspace_.resize(n);
  if (inertia_ == &body_inertia_) {
    for (size_t k = 0; k < n; ++k) {
      const ServoLink& l = links[k];
      if (!given) {
        body_inertia_[k] = spatialInertia(l.mass, l.com, l.inertia);
        body_subspace_[k] = motionSubspace(l);
      } else if (extra && !listed_extra_) {
        body_inertia_[k] = (*tree.inertia)[k];
      }
      if (extra && loads.links.empty()) body_inertia_[k] += loads.extra_inertia[k];
    }
  }
  if (extra && !given) {
    for (int k : loads.links) body_inertia_[k] += loads.extra_inertia[k];
  }
}

void HybridSweep::run(const std::vector<ServoLink>& links, bool fixed_root,
                      const std::vector<ServoDemand>& demands, const ServoLoads& loads,
                      ServoSolution& out) {
  const size_t n = links.size();
  const bool listed = !loads.links.empty();
  for (size_t k = 0; k < n; ++k) {
    articulated_[k] = (*inertia_)[k];
    // The bias impulse is what must act for no velocity change: minus the applied one.
    if (update_) {
      bias_[k] = step_bias_[k];
    } else if (loads.impulse.empty() || listed) {
      bias_[k].setZero();
    } else {
      bias_[k] = -loads.impulse[k];
    }
  }
  for (int k : loads.links) {
    if (listed_extra_) articulated_[k] += loads.extra_inertia[k];
    if (loads.impulse.empty()) continue;
    if (update_) {
      bias_[k] -= loads.impulse[k];
    } else {
      bias_[k] = -loads.impulse[k];
    }
  }
  inwardPass(links, demands);
  outwardPass(links, fixed_root, demands, out);
  ++out.passes;
}

// Leaves to root: articulated inertias and bias impulses.
void HybridSweep::inwardPass(const std::vector<ServoLink>& links,
                             const std::vector<ServoDemand>& demands) {
  const Vec6* s = subspace_->data();  // the joints' motion subspaces
  for (size_t k = links.size() - 1; k >= 1; --k) {
    const int p = links[k].parent;
    const Mat6& ia = articulated_[k];
    switch (status_[k]) {
      case JointStatus::kFixed:  // no joint velocity: no velocity product either
        articulated_[p] += ia;
        bias_[p] += bias_[k];
        break;
      case JointStatus::kFree: {
        const Vec6 u_vec = ia * s[k];
        const double d = s[k].dot(u_vec) + demands[k].spring_damping;
        u_vec_[k] = u_vec;
        d_[k] = d;
        u_[k] = (update_ ? tau_[k] + step_torque_[k] : tau_[k]) - s[k].dot(bias_[k]) +
                demands[k].spring_impulse;
        if (d > 0.0 && update_) {
          const Mat6 reduced = ia - u_vec * (u_vec.transpose() / d);
          articulated_[p] += reduced;
          bias_[p] += bias_[k] + reduced * step_coriolis_[k] + u_vec * (u_[k] / d);
        } else if (d > 0.0) {
          articulated_[p] += ia - u_vec * (u_vec.transpose() / d);
          bias_[p] += bias_[k] + u_vec * (u_[k] / d);
        } else {  // a subtree without inertia about its joint: carried along
          articulated_[p] += ia;
          bias_[p] += bias_[k];
          if (update_) bias_[p].noalias() += ia * step_coriolis_[k];
        }
        break;
      }
      case JointStatus::kPrescribed:
        articulated_[p] += ia;
        if (update_) {
          bias_[p] += bias_[k] + ia * (s[k] * demands[k].velocity_change + step_coriolis_[k]);
        } else {
          bias_[p] += bias_[k] + ia * (s[k] * demands[k].velocity_change);
        }
        break;
    }
  }
}

// Root to leaves: velocity changes and the driven joints' impulses.
void HybridSweep::outwardPass(const std::vector<ServoLink>& links, bool fixed_root,
                              const std::vector<ServoDemand>& demands, ServoSolution& out) {
  const Vec6* s = subspace_->data();  // the joints' motion subspaces
  const size_t n = links.size();
  if (fixed_root) {
    dv_[0].setZero();
  } else {
    dv_[0] = solveSymmetric(articulated_[0], -bias_[0]);
  }
  for (size_t k = 1; k < n; ++k) {
    Vec6 ap = dv_[links[k].parent];
    if (update_ && status_[k] != JointStatus::kFixed) ap += step_coriolis_[k];
    double dq = 0.0;
    switch (status_[k]) {
      case JointStatus::kFixed:
        out.impulse[k] = 0.0;
        break;
      case JointStatus::kFree:
        dq = d_[k] > 0.0 ? (u_[k] - u_vec_[k].dot(ap)) / d_[k] : 0.0;
        out.impulse[k] = tau_[k];
        break;
      case JointStatus::kPrescribed:
        dq = demands[k].velocity_change;
        break;
    }
    dv_[k] = ap + s[k] * dq;
    if (status_[k] == JointStatus::kPrescribed) {
      // The servo's share: less the step's joint torque and the implicit spring's impulse.
      const ServoDemand& d = demands[k];
      out.impulse[k] = s[k].dot(articulated_[k] * dv_[k] + bias_[k]) -
                       (d.spring_impulse - d.spring_damping * dq);
      if (update_) out.impulse[k] -= step_torque_[k];
    }
    out.velocity_change[k] = dq;
  }
  out.root_velocity_change = dv_[0];
  out.link_velocity_change.assign(dv_.begin(), dv_.begin() + static_cast<long>(n));
}

}  // namespace flapsim
