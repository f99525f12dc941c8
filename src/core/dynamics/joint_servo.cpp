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
                              const std::vector<ServoDemand>& demands, ServoSolution& out) {
  const size_t n = links.size();
  refill<signed char>(side_, n, 0);
  refill(out.impulse, n, 0.0);
  refill(out.velocity_change, n, 0.0);
  out.saturated.assign(n, false);
  out.passes = 0;
  int driven = 0;
  for (size_t k = 0; k < n; ++k) {
    const ServoLink& l = links[k];
    if (k == 0 || l.joint == ServoJointType::kFixed) {
      sweep_.setStatus(k, JointStatus::kFixed);
    } else if (demands[k].drives()) {
      ++driven;
      if (warm_.size() == n && warm_[k] != 0) {  // saturated in the last solve
        sweep_.setFree(k, warm_[k] > 0 ? demands[k].upper() : -demands[k].lower());
        side_[k] = warm_[k];
        out.saturated[k] = true;
      } else {
        sweep_.setStatus(k, JointStatus::kPrescribed);
      }
    } else {
      sweep_.setStatus(k, JointStatus::kFree);
    }
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
    sweep_.run(links, fixed_root, demands, loads, out);
    changed = false;
    for (size_t k = 1; k < n; ++k) {
      const ServoDemand& d = demands[k];
      if (!d.drives() || sweep_.status(k) == JointStatus::kFixed) continue;
      if (sweep_.status(k) == JointStatus::kPrescribed) {
        if (saturate(k, d, out.impulse[k])) {
          out.saturated[k] = true;
          changed = true;
        }
      } else if (out.saturated[k]) {
        // Re-driven when the bound it pushes with would carry it past its target.
        const double excess = out.velocity_change[k] - d.velocity_change;
        if ((side_[k] > 0 && excess > 0.0) || (side_[k] < 0 && excess < 0.0)) {
          sweep_.setStatus(k, JointStatus::kPrescribed);
          out.saturated[k] = false;
          changed = true;
        }
      }
    }
  }
  if (changed) {
    // Out of passes (a cycling active set, in theory): keep every bound.
    for (size_t k = 1; k < n; ++k) {
      if (sweep_.status(k) == JointStatus::kPrescribed && saturate(k, demands[k], out.impulse[k])) {
        out.saturated[k] = true;
      }
    }
    sweep_.run(links, fixed_root, demands, loads, out);
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
  sweep_.load(links, loads, tree);
  const int driven = prepare(links, demands, out);
  settleActiveSet(links, fixed_root, demands, loads, driven, out);
  warm_.resize(n);
  for (size_t k = 0; k < n; ++k) {
    warm_[k] = out.saturated[k] ? side_[k] : 0;
  }
}

bool JointServoSolver::saturate(size_t k, const ServoDemand& d, double impulse) {
  if (impulse > d.upper()) {
    sweep_.setFree(k, d.upper());
    side_[k] = 1;
    return true;
  }
  if (impulse < -d.lower()) {
    sweep_.setFree(k, -d.lower());
    side_[k] = -1;
    return true;
  }
  return false;
}

}  // namespace flapsim
