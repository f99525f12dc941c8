#include "dynamics/body_builder.h"

#include <algorithm>
#include <utility>
#include <vector>

#include "world/joint_drives.h"
#include "dynamics/joint_limit.h"

namespace flapsim {

namespace {

// Link k (>= 1) of the multibody, on the joint to its parent.
void setupLink(btMultiBody& mb, const CreatureModel& m, int k) {
  const LinkModel& l = m.links[k];
  const JointModel& j = m.joints[l.parent_joint];
  const LinkModel& p = m.links[j.parent_link];
  const btQuaternion rot = toBt(j.origin.orientation.conjugate());
  const btVector3 parent_com_to_pivot = toBt(j.origin.position - p.com);
  const btVector3 pivot_to_com = toBt(l.com);
  const int parent = j.parent_link - 1;
  switch (j.type) {
    case JointType::kRevolute:
    case JointType::kContinuous:
      mb.setupRevolute(k - 1, l.mass, toBt(l.inertia), parent, rot, toBt(j.axis),
                       parent_com_to_pivot, pivot_to_com, true);
      break;
    case JointType::kPrismatic:
      mb.setupPrismatic(k - 1, l.mass, toBt(l.inertia), parent, rot, toBt(j.axis),
                        parent_com_to_pivot, pivot_to_com, true);
      break;
    case JointType::kFixed:
      mb.setupFixed(k - 1, l.mass, toBt(l.inertia), parent, rot, parent_com_to_pivot, pivot_to_com);
      break;
  }
}

// The multibody of `m`, its root's COM at `pose` * root COM, moving with `twist`.
std::unique_ptr<btMultiBody> makeMultiBody(const CreatureModel& m, const Pose& pose,
                                           const Twist& twist) {
  const int n = static_cast<int>(m.links.size()) - 1;
  const LinkModel& root = m.links[0];
  auto mb = std::make_unique<btMultiBody>(n, root.mass, toBt(root.inertia), m.fixed_base, false);
  for (int k = 1; k <= n; ++k) setupLink(*mb, m, k);
  mb->finalizeMultiDof();
  mb->setLinearDamping(0);
  mb->setAngularDamping(0);
  mb->setMaxCoordinateVelocity(1e6);
  mb->setMaxAppliedImpulse(1e6);
  mb->setHasSelfCollision(false);
  mb->setUseGyroTerm(true);
  mb->setCanSleep(false);
  const Pose com_pose = pose * Pose{root.com, Quat::Identity()};
  mb->setBaseWorldTransform(toBt(com_pose));
  mb->setBaseVel(toBt(twist.linear));
  mb->setBaseOmega(toBt(twist.angular));
  return mb;
}

// Sizes the link frames and fills them from the multibody.
void initFrames(CreatureBody& body, int links) {
  body.frames.world_to_local.resize(links);
  body.frames.local_origin.resize(links);
  body.frames.omega.resize(links);
  body.frames.vel.resize(links);
  body.mb->forwardKinematics(body.frames.world_to_local, body.frames.local_origin);
}

// Distance from the link's COM to the farthest corner of its boxes (0 if none).
double linkReach(const LinkModel& l) {
  const Pose com_inv{-l.com, Quat::Identity()};
  double reach = 0.0;
  for (const Box& b : l.boxes) {
    const double corner = (com_inv * b.origin).position.norm() + 0.5 * b.size.norm();
    reach = std::max(reach, corner);
  }
  return reach;
}

// The collision shape of a link with boxes (in the COM frame), owned by `body`.
btCollisionShape* linkShape(CreatureBody& body, const LinkModel& l) {
  const Pose com_inv{-l.com, Quat::Identity()};
  const Pose first = com_inv * l.boxes[0].origin;
  if (l.boxes.size() == 1 && first.position.isZero(1e-12) &&
      first.orientation.isApprox(Quat::Identity(), 1e-12)) {
    // One box centred on the COM: no compound needed (cheaper contact tests).
    body.shapes.push_back(std::make_unique<btBoxShape>(toBt(0.5 * l.boxes[0].size)));
    return body.shapes.back().get();
  }
  auto compound = std::make_unique<btCompoundShape>(false, static_cast<int>(l.boxes.size()));
  for (const Box& b : l.boxes) {
    auto box = std::make_unique<btBoxShape>(toBt(0.5 * b.size));
    compound->addChildShape(toBt(com_inv * b.origin), box.get());
    body.shapes.push_back(std::move(box));
  }
  btCollisionShape* shape = compound.get();
  body.shapes.push_back(std::move(compound));
  return shape;
}

// The collider of link k (which has boxes), added to the scene.
void addCollider(CreatureBody& body, const LinkModel& l, int k, double friction) {
  btMultiBody* mb = body.mb.get();
  auto col = std::make_unique<btMultiBodyLinkCollider>(mb, k - 1);
  col->setCollisionShape(linkShape(body, l));
  col->setFriction(friction);
  col->setActivationState(DISABLE_DEACTIVATION);
  col->setWorldTransform(
      btTransform(body.frames.world_to_local[k].inverse(), body.frames.local_origin[k]));
  body.scene->world().addCollisionObject(col.get(), btBroadphaseProxy::DefaultFilter,
                                         btBroadphaseProxy::AllFilter);
  if (k == 0) {
    mb->setBaseCollider(col.get());
  } else {
    mb->getLink(k - 1).m_collider = col.get();
  }
  body.colliders.push_back(std::move(col));
}

// Colliders (boxes, in the COM frame) and reaches of every link.
void addColliders(CreatureBody& body, const CreatureModel& m, double friction) {
  body.reach.assign(m.links.size(), 0.0);
  for (size_t k = 0; k < m.links.size(); ++k) {
    const LinkModel& l = m.links[k];
    body.reach[k] = linkReach(l);
    if (!l.boxes.empty()) addCollider(body, l, static_cast<int>(k), friction);
  }
}

// Joint limits (one Bullet constraint for all, see joint_limit.h), servo effort bounds and
// capped damping.
void addLimits(CreatureBody& body, const CreatureModel& m, const WorldParams& params) {
  body.max_effort.assign(m.joints.size(), 0.0);
  body.damping.assign(m.joints.size(), 0.0);
  body.stiffness.assign(m.joints.size(), 0.0);
  std::vector<JointLimits::Limit> limits;
  for (size_t ji = 0; ji < m.joints.size(); ++ji) {
    const JointModel& j = m.joints[ji];
    if (!j.movable()) continue;
    if (j.limited && j.lower < j.upper) limits.push_back({j.child_link - 1, j.lower, j.upper});
    body.max_effort[ji] = j.effort > 0.0 ? j.effort : params.default_wing_effort;
    body.damping[ji] = std::min(j.damping, dampingLimit(m, j, params.step_size));
    body.stiffness[ji] = std::min(j.stiffness, stiffnessLimit(m, j, params.step_size));
  }
  if (limits.empty()) return;
  auto constraint = std::make_unique<JointLimits>(body.mb.get(), std::move(limits));
  body.scene->world().addMultiBodyConstraint(constraint.get());
  body.limits.push_back(std::move(constraint));
}

// The joint servos (ours, see CreatureBody::applyServos), one per model link.
void setupServos(CreatureBody& body, const CreatureModel& m) {
  const size_t links = m.links.size();
  body.model = &m;
  body.servo_target.assign(links, 0.0);
  body.demands.assign(links, ServoDemand());
  body.servo_links.resize(links);
  for (size_t k = 0; k < links; ++k) {
    const LinkModel& l = m.links[k];
    ServoLink& s = body.servo_links[k];
    s.mass = l.mass;
    if (k == 0) continue;
    const JointModel& j = m.joints[l.parent_joint];
    s.parent = j.parent_link;
    s.joint = j.type == JointType::kFixed       ? ServoJointType::kFixed
              : j.type == JointType::kPrismatic ? ServoJointType::kPrismatic
                                                : ServoJointType::kRevolute;
  }
}

}  // namespace

std::unique_ptr<CreatureBody> buildBody(const CreatureModel& m, const Pose& pose,
                                        const Twist& twist, const WorldParams& params) {
  auto body = std::make_unique<CreatureBody>();
  body->scene = std::make_unique<Scene>(params);
  body->mb = makeMultiBody(m, pose, twist);
  body->scene->world().addMultiBody(body->mb.get());
  initFrames(*body, static_cast<int>(m.links.size()));
  addColliders(*body, m, params.ground_friction);
  body->aero = makeAeroBodies(m, params.air);
  addLimits(*body, m, params);
  setupServos(*body, m);
  CreatureBody* b = body.get();
  body->scene->world().setServos([b] { b->applyServos(); });
  body->scene->world().setGroundCheck([b] { return b->mayTouch(); });
  body->updateKinematics();  // frames and velocities for the first step
  return body;
}

}  // namespace flapsim
