#include "dynamics/joint_servo.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace flapsim {

namespace {

// v.assign(n, x) for a vector that keeps its size from one solve to the next: a resize (a
// compare when the size is the same) and a fill, inline, instead of a call per vector.
template <class T>
void refill(std::vector<T>& v, size_t n, T x) {
  v.resize(n);
  std::fill(v.begin(), v.end(), x);
}

}  // namespace

Vec6 motionSubspace(const ServoLink& link) {
  Vec6 s = Vec6::Zero();
  switch (link.joint) {
    case ServoJointType::kRevolute:
      s.head<3>() = link.axis;
      s.tail<3>() = link.anchor.cross(link.axis);
      break;
    case ServoJointType::kPrismatic:
      s.tail<3>() = link.axis;
      break;
    case ServoJointType::kFixed:
      break;
  }
  return s;
}

void JointServoSolver::solve(const std::vector<ServoLink>& links, bool fixed_root,
                             const std::vector<ServoDemand>& demands, ServoSolution& out) {
  static const ServoLoads kNone;
  solve(links, fixed_root, demands, kNone, out);
}

void JointServoSolver::solve(const std::vector<ServoLink>& links, bool fixed_root,
                             const std::vector<ServoDemand>& demands, const ServoLoads& loads,
                             ServoSolution& out) {
  solve(links, fixed_root, demands, loads, ServoTree(), out);
}

void JointServoSolver::checkArguments(const std::vector<ServoLink>& links,
                                      const std::vector<ServoDemand>& demands,
                                      const ServoLoads& loads, const ServoTree& tree) const {
  const size_t n = links.size();
  if (demands.size() != n) {
    throw std::invalid_argument("JointServoSolver: " + std::to_string(demands.size()) +
                                " demands for " + std::to_string(n) + " links");
  }
  if (tree.inertia && tree.subspace && (tree.inertia->size() != n || tree.subspace->size() != n)) {
    throw std::invalid_argument("JointServoSolver: inertias or subspaces not one per link");
  }
  if (tree.bias &&
      (!tree.inertia || !tree.subspace || !tree.coriolis || !tree.joint_torque ||
       tree.bias->size() != n || tree.coriolis->size() != n || tree.joint_torque->size() != n)) {
    throw std::invalid_argument(
        "JointServoSolver: a velocity update needs inertias, subspaces, biases, velocity "
        "products and joint torques, one per link");
  }
  for (size_t size : {loads.extra_inertia.size(), loads.impulse.size()}) {
    if (size != 0 && size != n) {
      throw std::invalid_argument("JointServoSolver: " + std::to_string(size) + " loads for " +
                                  std::to_string(n) + " links");
    }
  }
  for (int k : loads.links) {
    if (k < 0 || static_cast<size_t>(k) >= n) {
      throw std::invalid_argument("JointServoSolver: loaded link " + std::to_string(k) + " of " +
                                  std::to_string(n));
    }
  }
}

int JointServoSolver::prepare(const std::vector<ServoLink>& links,
                              const std::vector<ServoDemand>& demands, const ServoLoads& loads,
                              const ServoTree& tree, ServoSolution& out) {
  const size_t n = links.size();
  const bool given = tree.inertia && tree.subspace;
  status_.resize(n);
  refill(tau_, n, 0.0);
  refill<signed char>(side_, n, 0);
  body_inertia_.resize(n);
  const bool extra = !loads.extra_inertia.empty();
  // Given inertias are read where they are, unless loads add to every link's.
  listed_extra_ = given && extra && !loads.links.empty();
  inertia_ = given && (!extra || listed_extra_) ? tree.inertia : &body_inertia_;
  articulated_.resize(n);
  bias_.resize(n);
  s_.resize(n);
  u_vec_.resize(n);
  dv_.resize(n);
  d_.resize(n);
  u_.resize(n);
  refill(out.impulse, n, 0.0);
  refill(out.velocity_change, n, 0.0);
  out.saturated.assign(n, false);
  out.passes = 0;
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

  int driven = 0;
  for (size_t k = 0; k < n; ++k) {
    const ServoLink& l = links[k];
    if (!given) {
      body_inertia_[k] = spatialInertia(l.mass, l.com, l.inertia);
    } else if (extra && !listed_extra_) {
      body_inertia_[k] = (*tree.inertia)[k];
    }
    if (extra && loads.links.empty()) body_inertia_[k] += loads.extra_inertia[k];
    s_[k] = given ? (*tree.subspace)[k] : motionSubspace(l);
    if (k == 0 || l.joint == ServoJointType::kFixed) {
      status_[k] = Status::kFixed;
    } else if (demands[k].drives()) {
      ++driven;
      if (warm_.size() == n && warm_[k] != 0) {  // saturated in the last solve
        status_[k] = Status::kFree;
        side_[k] = warm_[k];
        tau_[k] = warm_[k] > 0 ? demands[k].upper() : -demands[k].lower();
        out.saturated[k] = true;
      } else {
        status_[k] = Status::kPrescribed;
      }
    } else {
      status_[k] = Status::kFree;
    }
  }

  if (extra && !given) {
    for (int k : loads.links) body_inertia_[k] += loads.extra_inertia[k];
  }

  return driven;
}

void JointServoSolver::settleActiveSet(const std::vector<ServoLink>& links, bool fixed_root,
                                       const std::vector<ServoDemand>& demands,
                                       const ServoLoads& loads, int driven, ServoSolution& out) {
  const size_t n = links.size();
  // Active set: a driven joint whose impulse would exceed its bound pushes with the bound
  // instead; a pushing joint whose bound would carry it past its target is driven again.
  const int max_passes = std::min(2 * driven + 2, 32);
  bool changed = true;
  while (changed && out.passes < max_passes) {
    pass(links, fixed_root, demands, loads, out);
    changed = false;
    for (size_t k = 1; k < n; ++k) {
      const ServoDemand& d = demands[k];
      if (!d.drives() || status_[k] == Status::kFixed) continue;
      if (status_[k] == Status::kPrescribed) {
        if (saturate(k, d, out.impulse[k])) {
          out.saturated[k] = true;
          changed = true;
        }
      } else if (out.saturated[k]) {
        // Re-driven when the bound it pushes with would carry it past its target.
        const double excess = out.velocity_change[k] - d.velocity_change;
        if ((side_[k] > 0 && excess > 0.0) || (side_[k] < 0 && excess < 0.0)) {
          status_[k] = Status::kPrescribed;
          out.saturated[k] = false;
          changed = true;
        }
      }
    }
  }
  if (changed) {
    // Out of passes (a cycling active set, in theory): keep every bound.
    for (size_t k = 1; k < n; ++k) {
      if (status_[k] == Status::kPrescribed && saturate(k, demands[k], out.impulse[k])) {
        out.saturated[k] = true;
      }
    }
    pass(links, fixed_root, demands, loads, out);
  }
}

void JointServoSolver::solve(const std::vector<ServoLink>& links, bool fixed_root,
                             const std::vector<ServoDemand>& demands, const ServoLoads& loads,
                             const ServoTree& tree, ServoSolution& out) {
  checkArguments(links, demands, loads, tree);
  const size_t n = links.size();
  out.root_velocity_change.setZero();
  if (n == 0) {
    out.impulse.clear();
    out.velocity_change.clear();
    out.link_velocity_change.clear();
    out.saturated.clear();
    out.passes = 0;
    return;
  }
  const int driven = prepare(links, demands, loads, tree, out);
  settleActiveSet(links, fixed_root, demands, loads, driven, out);
  warm_.resize(n);
  for (size_t k = 0; k < n; ++k) {
    warm_[k] = out.saturated[k] ? side_[k] : 0;
  }
}

bool JointServoSolver::saturate(size_t k, const ServoDemand& d, double impulse) {
  if (impulse > d.upper()) {
    status_[k] = Status::kFree;
    tau_[k] = d.upper();
    side_[k] = 1;
    return true;
  }
  if (impulse < -d.lower()) {
    status_[k] = Status::kFree;
    tau_[k] = -d.lower();
    side_[k] = -1;
    return true;
  }
  return false;
}

void JointServoSolver::pass(const std::vector<ServoLink>& links, bool fixed_root,
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
void JointServoSolver::inwardPass(const std::vector<ServoLink>& links,
                                  const std::vector<ServoDemand>& demands) {
  for (size_t k = links.size() - 1; k >= 1; --k) {
    const int p = links[k].parent;
    const Mat6& ia = articulated_[k];
    switch (status_[k]) {
      case Status::kFixed:  // no joint velocity: no velocity product either
        articulated_[p] += ia;
        bias_[p] += bias_[k];
        break;
      case Status::kFree: {
        const Vec6 u_vec = ia * s_[k];
        const double d = s_[k].dot(u_vec) + demands[k].spring_damping;
        u_vec_[k] = u_vec;
        d_[k] = d;
        u_[k] = (update_ ? tau_[k] + step_torque_[k] : tau_[k]) - s_[k].dot(bias_[k]) +
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
      case Status::kPrescribed:
        articulated_[p] += ia;
        if (update_) {
          bias_[p] += bias_[k] + ia * (s_[k] * demands[k].velocity_change + step_coriolis_[k]);
        } else {
          bias_[p] += bias_[k] + ia * (s_[k] * demands[k].velocity_change);
        }
        break;
    }
  }
}

// Root to leaves: velocity changes and the driven joints' impulses.
void JointServoSolver::outwardPass(const std::vector<ServoLink>& links, bool fixed_root,
                                   const std::vector<ServoDemand>& demands, ServoSolution& out) {
  const size_t n = links.size();
  if (fixed_root) {
    dv_[0].setZero();
  } else {
    dv_[0] = solveSymmetric(articulated_[0], -bias_[0]);
  }
  for (size_t k = 1; k < n; ++k) {
    Vec6 ap = dv_[links[k].parent];
    if (update_ && status_[k] != Status::kFixed) ap += step_coriolis_[k];
    double dq = 0.0;
    switch (status_[k]) {
      case Status::kFixed:
        out.impulse[k] = 0.0;
        break;
      case Status::kFree:
        dq = d_[k] > 0.0 ? (u_[k] - u_vec_[k].dot(ap)) / d_[k] : 0.0;
        out.impulse[k] = tau_[k];
        break;
      case Status::kPrescribed:
        dq = demands[k].velocity_change;
        break;
    }
    dv_[k] = ap + s_[k] * dq;
    if (status_[k] == Status::kPrescribed) {
      // The servo's share: less the step's joint torque and the implicit spring's impulse.
      const ServoDemand& d = demands[k];
      out.impulse[k] = s_[k].dot(articulated_[k] * dv_[k] + bias_[k]) -
                       (d.spring_impulse - d.spring_damping * dq);
      if (update_) out.impulse[k] -= step_torque_[k];
    }
    out.velocity_change[k] = dq;
  }
  out.root_velocity_change = dv_[0];
  out.link_velocity_change.assign(dv_.begin(), dv_.begin() + static_cast<long>(n));
}

}  // namespace flapsim
