#include "dynamics/tree_dynamics.h"

#include <cstring>

#include "dynamics/bullet_scene.h"

namespace flapsim {

namespace {

// A force and a torque (world frame, at a body's COM `com`) as a spatial force about the
// base's COM.
Vec6 spatialForce(const btVector3& force, const btVector3& torque, const Vec3& com) {
  const Vec3 f = fromBt(force);
  Vec6 out;
  out << fromBt(torque) + com.cross(f), f;
  return out;
}

// What spatialInertia(mass, com, rot diag(d) rot^T) is, written into `out`: the rotated
// inertia is symmetric, so its six distinct entries are summed once each.
void setSpatialInertia(double mass, const Vec3& com, const Mat3& rot, const Vec3& d, Mat6& out) {
  const Vec3 mc = mass * com;
  const double mcc = mc.dot(com);
  double rd[3][3];  // rot diag(d), each product once
  for (int i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) rd[i][k] = rot(i, k) * d[k];
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      double v =
          rd[i][0] * rot(j, 0) + rd[i][1] * rot(j, 1) + rd[i][2] * rot(j, 2) - mc[i] * com[j];
      if (i == j) v += mcc;
      out(i, j) = v;
      out(j, i) = v;
    }
  }
  out.topRightCorner<3, 3>() << 0.0, -mc.z(), mc.y(), mc.z(), 0.0, -mc.x(), -mc.y(), mc.x(), 0.0;
  out.bottomLeftCorner<3, 3>() = -out.topRightCorner<3, 3>();
  out.bottomRightCorner<3, 3>() = mass * Mat3::Identity();
}

}  // namespace

bool TreeDynamics::handles(const btMultiBody& mb) {
  if (mb.getLinearDamping() != 0 || mb.getAngularDamping() != 0 || !mb.getUseGyroTerm()) {
    return false;
  }
  for (int i = 0; i < mb.getNumLinks(); ++i) {
    const btMultibodyLink& l = mb.getLink(i);
    if (l.m_jointType != btMultibodyLink::eRevolute &&
        l.m_jointType != btMultibodyLink::ePrismatic && l.m_jointType != btMultibodyLink::eFixed) {
      return false;
    }
    if (mb.isLinkKinematic(i) || l.m_jointFeedback) return false;
  }
  return true;
}

// Rotations, COMs, spatial inertias and joint axes, about the base's COM, as
// btMultiBody::forwardKinematics places the links.
void TreeDynamics::linkFrames(const btMultiBody& mb) {
  const int n = mb.getNumLinks();
  for (auto* v : {&inv_d_, &u_}) v->resize(n + 1);
  to_local_.resize(n + 1);
  rot_.resize(n + 1);
  com_.resize(n + 1);
  axis_.resize(n + 1);
  body_.resize(n + 1);
  to_local_[0] = mb.getWorldToBaseRot();
  rot_[0] = fromBt(to_local_[0].inverse()).toRotationMatrix();
  com_[0].setZero();
  setSpatialInertia(mb.getBaseMass(), com_[0], rot_[0], fromBt(mb.getBaseInertia()), body_[0]);
  axis_[0].setZero();
  for (int k = 0; k < n; ++k) {
    const btMultibodyLink& l = mb.getLink(k);
    const int b = k + 1, p = l.m_parent + 1;
    to_local_[b] = l.m_cachedRotParentToThis * to_local_[p];
    rot_[b] = fromBt(to_local_[b].inverse()).toRotationMatrix();
    com_[b] = com_[p] + rot_[b] * fromBt(l.m_cachedRVector);
    setSpatialInertia(l.m_mass, com_[b], rot_[b], fromBt(l.m_inertiaLocal), body_[b]);
    axis_[b].setZero();
    if (l.m_dofCount == 1) {
      // Bullet's axis moves the link's COM (linear part); about the base's COM instead.
      const Vec3 w = rot_[b] * fromBt(l.m_axes[0].m_topVec);
      axis_[b] << w, rot_[b] * fromBt(l.m_axes[0].m_bottomVec) + com_[b].cross(w);
    }
  }
}

bool TreeDynamics::framesCurrent(const btMultiBody& mb) {
  constexpr int kPerLink = 11;
  const int n = mb.getNumLinks();
  inputs_.resize(8 + kPerLink * static_cast<size_t>(n));
  btScalar* in = inputs_.data();
  auto add = [&in](const btScalar* v, int count) {
    for (int i = 0; i < count; ++i) *in++ = v[i];
  };
  const btQuaternion base = mb.getWorldToBaseRot();
  add(&base[0], 4);
  const btScalar base_mass = mb.getBaseMass();
  add(&base_mass, 1);
  add(mb.getBaseInertia().m_floats, 3);
  for (int k = 0; k < n; ++k) {
    const btMultibodyLink& l = mb.getLink(k);
    add(&l.m_cachedRotParentToThis[0], 4);
    add(l.m_cachedRVector.m_floats, 3);
    add(l.m_inertiaLocal.m_floats, 3);
    add(&l.m_mass, 1);
  }
  // Bit for bit: the frames made of equal inputs are equal.
  const bool same =
      framed_ == &mb && frame_inputs_.size() == inputs_.size() &&
      std::memcmp(frame_inputs_.data(), inputs_.data(), inputs_.size() * sizeof(btScalar)) == 0;
  if (!same) {
    framed_ = &mb;
    frame_inputs_.swap(inputs_);
  }
  return same;
}

void TreeDynamics::updateFrames(const btMultiBody& mb) {
  if (!framesCurrent(mb)) linkFrames(mb);
}

const std::vector<Vec6, Eigen::aligned_allocator<Vec6>>& TreeDynamics::velocities(
    const btMultiBody& mb) {
  const int n = mb.getNumLinks();
  velocity_.resize(n + 1);
  velocity_[0] << fromBt(mb.getBaseOmega()), fromBt(mb.getBaseVel());
  for (int k = 0; k < n; ++k) {
    const btMultibodyLink& l = mb.getLink(k);
    const int b = k + 1, p = l.m_parent + 1;
    velocity_[b] = velocity_[p];
    if (l.m_dofCount == 1) velocity_[b] += axis_[b] * jointVel(mb, k);
  }
  return velocity_;
}

// Spatial velocities, velocity-product accelerations and the bias forces (velocity
// products minus applied forces), which start the articulated bias.
void TreeDynamics::velocitiesAndBias(const btMultiBody& mb) {
  const int n = mb.getNumLinks();
  velocities(mb);
  coriolis_.resize(n + 1);
  bias_.resize(n + 1);
  torque_.resize(n + 1);
  torque_[0] = 0.0;
  coriolis_[0].setZero();
  bias_[0] = crossForce(velocity_[0], body_[0] * velocity_[0]) -
             spatialForce(mb.getBaseForce(), mb.getBaseTorque(), com_[0]);
  for (int k = 0; k < n; ++k) {
    const btMultibodyLink& l = mb.getLink(k);
    const int b = k + 1;
    const Vec6 joint = axis_[b] * (l.m_dofCount == 1 ? jointVel(mb, k) : 0.0);
    coriolis_[b] = crossMotion(velocity_[b], joint);
    bias_[b] = crossForce(velocity_[b], body_[b] * velocity_[b]) -
               spatialForce(l.m_appliedForce, l.m_appliedTorque, com_[b]);
    torque_[b] = l.m_dofCount == 1 ? mb.getJointTorque(k) : 0.0;
  }
}

// Leaves to root: articulated inertias and bias forces.
void TreeDynamics::inwardPass(const btMultiBody& mb) {
  const int n = mb.getNumLinks();
  u_vec_.resize(n + 1);
  inertia_ = body_;
  for (int k = n - 1; k >= 0; --k) {
    const btMultibodyLink& l = mb.getLink(k);
    const int b = k + 1, p = l.m_parent + 1;
    Mat6& ia = inertia_[b];
    Vec6& pa = bias_[b];
    if (l.m_dofCount == 1) {
      u_vec_[b] = ia * axis_[b];
      const double d = axis_[b].dot(u_vec_[b]);
      inv_d_[b] = d >= SIMD_EPSILON ? 1.0 / d : 0.0;  // Bullet's guard
      u_[b] = torque_[b] - axis_[b].dot(pa);
      ia.noalias() -= (u_vec_[b] * inv_d_[b]) * u_vec_[b].transpose();
      pa += ia * coriolis_[b] + u_vec_[b] * (u_[b] * inv_d_[b]);
    } else {
      pa += ia * coriolis_[b];
    }
    inertia_[p] += ia;
    bias_[p] += pa;
  }
}

// Root to leaves: accelerations, in Bullet's velocity order.
void TreeDynamics::outwardPass(const btMultiBody& mb) {
  const int n = mb.getNumLinks();
  accel_.resize(n + 1);
  out_.assign(6 + static_cast<size_t>(mb.getNumDofs()), 0.0);
  if (mb.hasFixedBase()) {
    accel_[0].setZero();
  } else {
    accel_[0] = -solveSymmetric(inertia_[0], bias_[0]);  // symmetric positive definite
  }
  // The base COM's acceleration: the spatial one plus omega x v.
  const Vec3 base_linear =
      accel_[0].tail<3>() + velocity_[0].head<3>().cross(velocity_[0].tail<3>());
  out_[0] = accel_[0][0];
  out_[1] = accel_[0][1];
  out_[2] = accel_[0][2];
  out_[3] = base_linear[0];
  out_[4] = base_linear[1];
  out_[5] = base_linear[2];
  for (int k = 0; k < n; ++k) {
    const btMultibodyLink& l = mb.getLink(k);
    const int b = k + 1, p = l.m_parent + 1;
    accel_[b] = accel_[p] + coriolis_[b];
    if (l.m_dofCount != 1) continue;
    const double qdd = (u_[b] - u_vec_[b].dot(accel_[b])) * inv_d_[b];
    accel_[b] += axis_[b] * qdd;
    out_[6 + static_cast<size_t>(l.m_dofOffset)] = qdd;
  }
}

const std::vector<double>& TreeDynamics::accelerations(const btMultiBody& mb) {
  updateFrames(mb);
  velocitiesAndBias(mb);
  inwardPass(mb);
  outwardPass(mb);
  return out_;
}

void TreeDynamics::beginStep(const btMultiBody& mb, double dt) {
  updateFrames(mb);
  velocitiesAndBias(mb);
  dt_ = dt;
  pending_ = true;
}

Vec3 TreeDynamics::baseLinearBias() const {
  return dt_ * velocity_[0].head<3>().cross(velocity_[0].tail<3>());
}

void TreeDynamics::finishVelocityStep(btMultiBody& mb) {
  if (!pending_) return;
  pending_ = false;
  inwardPass(mb);
  outwardPass(mb);
  const std::vector<double>& a = out_;
  const double dt = dt_;
  const btScalar most = mb.getMaxCoordinateVelocity();
  auto add = [dt, most](btScalar v, double acc) {
    btScalar out = v + acc * dt;
    btClamp(out, -most, most);
    return out;
  };
  const btVector3 w = mb.getBaseOmega(), v = mb.getBaseVel();
  mb.setBaseOmega(btVector3(add(w.x(), a[0]), add(w.y(), a[1]), add(w.z(), a[2])));
  mb.setBaseVel(btVector3(add(v.x(), a[3]), add(v.y(), a[4]), add(v.z(), a[5])));
  for (int k = 0; k < mb.getNumLinks(); ++k) {
    const btMultibodyLink& l = mb.getLink(k);
    if (l.m_dofCount == 1) mb.setJointVel(k, add(jointVel(mb, k), a[6 + l.m_dofOffset]));
  }
}

}  // namespace flapsim
