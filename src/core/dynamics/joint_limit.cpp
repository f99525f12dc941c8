#include "dynamics/joint_limit.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <algorithm>
#include <utility>

#include "dynamics/bullet_scene.h"

namespace flapsim {

namespace {

// How far (rad or m) from a bound a joint at rest counts as able to reach it in a step;
// a moving joint adds twice its step's travel.
constexpr btScalar kMargin = 1e-3;

// Where joint `l` stands: `direction` +1 for its lower bound (the row pushes the joint up),
// -1 for its upper bound; `gap` >= 0 while inside.
struct Nearer {
  btScalar direction;
  btScalar gap;
};

Nearer nearer(const JointLimits::Limit& l, btScalar q) {
  if (l.upper - q < q - l.lower) return Nearer{-1, l.upper - q};
  return Nearer{1, q - l.lower};
}

}  // namespace

JointLimits::JointLimits(btMultiBody* body, std::vector<Limit> limits)
    : btMultiBodyConstraint(body, body, limits.at(0).link, body->getLink(limits[0].link).m_parent,
                            static_cast<int>(limits.size()), true, MULTIBODY_CONSTRAINT_LIMIT),
      limits_(std::move(limits)) {
  m_maxAppliedImpulse = 1e6;  // as the multibody's own bound (bullet_body.cpp)
}

bool JointLimits::mayReach(const Limit& l, btScalar dt) const {
  // Every step: Bullet's getJointPos and getJointVel inline (they are not).
  const Nearer n = nearer(l, m_bodyA->getLink(l.link).m_jointPos[0]);
  const btScalar approach = -n.direction * jointVel(*m_bodyA, l.link);
  return n.gap <= kMargin + 2 * dt * std::max<btScalar>(approach, 0);
}

bool JointLimits::mayAct(btScalar dt) const {
  for (const Limit& l : limits_) {
    if (mayReach(l, dt)) return true;
  }
  return false;
}

bool JointLimits::omittedMayReach(btScalar dt) const {
  for (size_t k = 0; k < omitted_.size(); ++k) {
    if (omitted_[k] && mayReach(limits_[k], dt)) return true;
  }
  return false;
}

void JointLimits::finalizeMultiDof() {
  allocateJacobiansMultiDof();
  m_numDofsFinalized = m_jacSizeBoth;
}

int JointLimits::getIslandIdA() const {
  if (const btMultiBodyLinkCollider* col = m_bodyA->getBaseCollider()) return col->getIslandTag();
  for (int i = 0; i < m_bodyA->getNumLinks(); ++i) {
    if (const btMultiBodyLinkCollider* col = m_bodyA->getLink(i).m_collider) {
      return col->getIslandTag();
    }
  }
  return -1;
}

int JointLimits::getIslandIdB() const { return getIslandIdA(); }

void JointLimits::createConstraintRows(btMultiBodyConstraintArray& rows,
                                       btMultiBodyJacobianData& data,
                                       const btContactSolverInfo& info) {
  if (m_numDofsFinalized != m_jacSizeBoth) finalizeMultiDof();
  const btScalar dt = info.m_timeStep;
  omitted_.assign(limits_.size(), 0);
  if (!mayAct(dt)) return;

  const btVector3 zero(0, 0, 0);
  for (int row = 0; row < static_cast<int>(limits_.size()); ++row) {
    const Limit& l = limits_[row];
    if (near_rows_only_ && !mayReach(l, dt)) {
      omitted_[row] = 1;
      continue;
    }
    const Nearer n = nearer(l, m_bodyA->getJointPos(l.link));
    const btMultibodyLink& link = m_bodyA->getLink(l.link);
    btScalar* jacobian = jacobianA(row);
    std::fill(jacobian, jacobian + m_jacSizeA, btScalar(0));
    jacobian[6 + link.m_dofOffset] = n.direction;  // on the A side: see the header

    btMultiBodySolverConstraint& c = rows.expandNonInitializing();
    c.m_orgConstraint = this;
    c.m_orgDofIndex = row;
    c.m_multiBodyA = m_bodyA;
    c.m_multiBodyB = m_bodyB;
    const btScalar rel_vel = fillMultiBodyConstraint(c, data, jacobian, jacobianB(row), zero, zero,
                                                     zero, zero, 0, info, 0, m_maxAppliedImpulse);
    const btQuaternion to_world = link.m_cachedWorldTransform.getRotation();
    c.m_contactNormal1.setZero();
    c.m_contactNormal2.setZero();
    c.m_relpos1CrossNormal.setZero();
    c.m_relpos2CrossNormal.setZero();
    if (link.m_jointType == btMultibodyLink::ePrismatic) {
      const btVector3 axis = n.direction * quatRotate(to_world, link.m_axes[0].m_bottomVec);
      c.m_contactNormal1 = axis;
      c.m_contactNormal2 = -axis;
    } else {
      const btVector3 axis = n.direction * quatRotate(to_world, link.m_axes[0].m_topVec);
      c.m_relpos1CrossNormal = axis;
      c.m_relpos2CrossNormal = -axis;
    }
    // The joint's velocity away from the bound (rel_vel) must end the step at least
    // -gap / dt (inside: it may close the gap, no more) or, beyond the bound, at least the
    // error reduction's share of the way back.
    const btScalar wanted = n.gap >= 0 ? -n.gap / dt : -n.gap * info.m_erp2 / dt;
    c.m_rhs = (wanted - rel_vel) * c.m_jacDiagABInv;
    c.m_rhsPenetration = 0;
  }
}

}  // namespace flapsim
