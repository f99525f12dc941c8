#include "dynamics/bullet_body.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

#include "dynamics/joint_limit.h"

namespace flapsim {

BodyKinematics LinkFrames::kinematics(int k, Mat3* rotation) const {
  BodyKinematics kin;
  kinematics(k, kin);
  if (rotation) *rotation = kin.rotation;
  return kin;
}

void LinkFrames::kinematics(int k, BodyKinematics& kin) const {
  kin.orientation = fromBt(world_to_local_[k].inverse());
  // One rotation matrix for both velocities: cheaper than two quaternion rotations.
  kin.rotation = rotation_[k];
  kin.com = fromBt(local_origin_[k]);
  // Bullet's link velocities are in the link's (COM) frame.
  kin.body_linear_velocity = fromBt(vel_[k]);
  kin.body_angular_velocity = fromBt(omega_[k]);
  kin.linear_velocity = kin.rotation * kin.body_linear_velocity;
  kin.angular_velocity = kin.rotation * kin.body_angular_velocity;
  kin.has_body_frame = true;
}

JointAxis BulletBody::jointAxis(const JointModel& j) const {
  const int k = j.child_link;
  const btMultibodyLink& link = mb_->getLink(k - 1);
  const Mat3& to_world = frames_.rotation(k);
  const Vec3 com = fromBt(frames_.com(k));
  if (j.type == JointType::kPrismatic) {
    return JointAxis{to_world * fromBt(link.m_axes[0].m_bottomVec), com};
  }
  // The pivot: the COM less the pivot-to-COM vector (Bullet's, in the link's frame).
  return JointAxis{to_world * fromBt(link.m_axes[0].m_topVec),
                   com - to_world * fromBt(link.m_dVector)};
}

void LinkFrames::resize(int links) {
  world_to_local_.resize(links);
  rotation_.resize(static_cast<size_t>(links));
  local_origin_.resize(links);
  omega_.resize(static_cast<size_t>(links));
  vel_.resize(static_cast<size_t>(links));
}

void LinkFrames::updateRotations() {
  for (int k = 0; k < world_to_local_.size(); ++k) {
    rotation_[k] = fromBt(world_to_local_[k].inverse()).toRotationMatrix();
  }
}

void BodySnapshot::take(const btMultiBody& mb) {
  position = mb.getBasePos();
  orientation = mb.getWorldToBaseRot();
  velocity = mb.getBaseVel();
  omega = mb.getBaseOmega();
  q.resize(static_cast<size_t>(mb.getNumLinks()));
  qdot.resize(q.size());
  for (int k = 0; k < mb.getNumLinks(); ++k) {
    q[k] = mb.getJointPos(k);
    qdot[k] = mb.getJointVel(k);
  }
}

void BodySnapshot::restore(btMultiBody& mb) const {
  mb.setBasePos(position);
  mb.setWorldToBaseRot(orientation);
  mb.setBaseVel(velocity);
  mb.setBaseOmega(omega);
  for (int k = 0; k < mb.getNumLinks(); ++k) {
    mb.setJointPos(k, q[k]);
    mb.setJointVel(k, qdot[k]);
  }
}

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

// The multibody of `m`, its root's COM where `pose` (the root's URDF frame) puts it, moving with
// `twist`.
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
  const Pose com_pose = root.fromUrdf(pose) * Pose{root.com, Quat::Identity()};
  mb->setBaseWorldTransform(toBt(com_pose));
  mb->setBaseVel(toBt(twist.linear));
  mb->setBaseOmega(toBt(twist.angular));
  return mb;
}

// Distance from the link's COM to the farthest corner of its boxes (0 if none).
double linkReach(const LinkModel& l) {
  const Pose com_inv{-l.com, Quat::Identity()};
  double reach = 0.0;
  for (const Box& b : l.boxes) {
    const double corner = (com_inv * b.origin).position.norm() + 0.5 * b.size.norm();
    reach = std::max(reach, corner);
  }
  for (const RoundShape& r : l.rounds) {
    const double rim = std::hypot(r.radius, 0.5 * r.length);  // a sphere's length is 0
    reach = std::max(reach, (com_inv * r.origin).position.norm() + rim);
  }
  for (const MeshShape& m : l.meshes) {
    const Pose frame = com_inv * m.origin;
    for (const Vec3& v : m.mesh->vertices) reach = std::max(reach, frame.apply(v).norm());
  }
  return reach;
}

// The convex hull of `points` (its vertices only: optimizeConvexHull), rounded by a margin of
// kHullMargin: it rests that far above what it lies on.
std::unique_ptr<btConvexHullShape> hullOf(const std::vector<Vec3>& points) {
  auto hull = std::make_unique<btConvexHullShape>();
  for (const Vec3& v : points) hull->addPoint(toBt(v), false);
  hull->recalcLocalAabb();
  hull->optimizeConvexHull();
  hull->setMargin(kHullMargin);
  return hull;
}

}  // namespace

std::vector<std::unique_ptr<btConvexHullShape>> meshColliders(const MeshShape& mesh) {
  std::vector<std::unique_ptr<btConvexHullShape>> hulls;
  if (!mesh.parts) {
    hulls.push_back(hullOf(mesh.mesh->vertices));
    return hulls;
  }
  for (const std::vector<Vec3>& part : *mesh.parts) hulls.push_back(hullOf(part));
  return hulls;
}

BulletBody::BulletBody(const CreatureModel& m, const Pose& pose, const Twist& twist,
                       const WorldParams& params)
    : model_(m), scene_(std::make_unique<Scene>(params)), mb_(makeMultiBody(m, pose, twist)) {
  world().addMultiBody(mb_.get());
  const int links = static_cast<int>(m.links.size());
  frames_.resize(links);
  mb_->forwardKinematics(frames_.world_to_local_, frames_.local_origin_);
  addColliders(params.ground_friction);
  addLimits();
  world().setGroundCheck([this] { return mayTouch(); });
  updateKinematics();  // frames and velocities for the first step
}

BulletBody::~BulletBody() {
  if (!scene_) return;
  btMultiBodyDynamicsWorld& w = world();
  for (auto& l : limits_) w.removeMultiBodyConstraint(l.get());
  for (auto& c : colliders_) w.removeCollisionObject(c.get());
  if (mb_) w.removeMultiBody(mb_.get());
}

// The collision shape of a link with shapes (in the COM frame), owned by the body.
btCollisionShape* BulletBody::linkShape(const LinkModel& l) {
  const Pose com_inv{-l.com, Quat::Identity()};
  if (l.boxes.empty() || !l.rounds.empty() || !l.meshes.empty()) return roundLinkShape(l);
  const Pose first = com_inv * l.boxes[0].origin;
  if (l.boxes.size() == 1 && first.position.isZero(1e-12) &&
      first.orientation.isApprox(Quat::Identity(), 1e-12)) {
    // One box centred on the COM: no compound needed (cheaper contact tests).
    shapes_.push_back(std::make_unique<btBoxShape>(toBt(0.5 * l.boxes[0].size)));
    return shapes_.back().get();
  }
  auto compound = std::make_unique<btCompoundShape>(false, static_cast<int>(l.boxes.size()));
  for (const Box& b : l.boxes) {
    auto box = std::make_unique<btBoxShape>(toBt(0.5 * b.size));
    compound->addChildShape(toBt(com_inv * b.origin), box.get());
    shapes_.push_back(std::move(box));
  }
  btCollisionShape* shape = compound.get();
  shapes_.push_back(std::move(compound));
  return shape;
}

// The compound shape of a link with cylinders or spheres (btCylinderShapeZ: URDF's axis z),
// meshes (meshColliders) and its boxes, in the COM frame, owned by the body.
btCollisionShape* BulletBody::roundLinkShape(const LinkModel& l) {
  const Pose com_inv{-l.com, Quat::Identity()};
  auto compound = std::make_unique<btCompoundShape>(
      false, static_cast<int>(l.boxes.size() + l.rounds.size() + l.meshes.size()));
  auto add = [&](std::unique_ptr<btCollisionShape> child, const Pose& origin) {
    compound->addChildShape(toBt(com_inv * origin), child.get());
    shapes_.push_back(std::move(child));
  };
  for (const Box& b : l.boxes) add(std::make_unique<btBoxShape>(toBt(0.5 * b.size)), b.origin);
  for (const RoundShape& r : l.rounds) {
    if (r.kind == RoundShape::Kind::kSphere) {
      add(std::make_unique<btSphereShape>(r.radius), r.origin);
    } else {
      const btVector3 half(r.radius, r.radius, 0.5 * r.length);
      add(std::make_unique<btCylinderShapeZ>(half), r.origin);
    }
  }
  for (const MeshShape& m : l.meshes) {
    for (auto& hull : meshColliders(m)) add(std::move(hull), m.origin);
  }
  btCollisionShape* shape = compound.get();
  shapes_.push_back(std::move(compound));
  return shape;
}

// The collider of link k (which has shapes), added to the scene.
void BulletBody::addCollider(const LinkModel& l, int k, double friction) {
  auto col = std::make_unique<btMultiBodyLinkCollider>(mb_.get(), k - 1);
  col->setCollisionShape(linkShape(l));
  col->setFriction(friction);
  col->setActivationState(DISABLE_DEACTIVATION);
  col->setWorldTransform(
      btTransform(frames_.world_to_local_[k].inverse(), frames_.local_origin_[k]));
  world().addCollisionObject(col.get(), btBroadphaseProxy::DefaultFilter,
                             btBroadphaseProxy::AllFilter);
  if (k == 0) {
    mb_->setBaseCollider(col.get());
  } else {
    mb_->getLink(k - 1).m_collider = col.get();
  }
  colliders_.push_back(std::move(col));
}

// Colliders (boxes, in the COM frame) and reaches of every link.
void BulletBody::addColliders(double friction) {
  reach_.assign(model_.links.size(), 0.0);
  for (size_t k = 0; k < model_.links.size(); ++k) {
    const LinkModel& l = model_.links[k];
    reach_[k] = linkReach(l);
    if (l.hasShapes()) addCollider(l, static_cast<int>(k), friction);
  }
}

// Joint limits: one Bullet constraint for all (see joint_limit.h).
void BulletBody::addLimits() {
  std::vector<JointLimits::Limit> limits;
  for (const JointModel& j : model_.joints) {
    if (j.movable() && j.limited && j.lower < j.upper) {
      limits.push_back({j.child_link - 1, j.lower, j.upper});
    }
  }
  if (limits.empty()) return;
  auto constraint = std::make_unique<JointLimits>(mb_.get(), std::move(limits));
  world().addMultiBodyConstraint(constraint.get());
  limits_.push_back(std::move(constraint));
}

void BulletBody::updateKinematics() {
  mb_->forwardKinematics(frames_.world_to_local_, frames_.local_origin_);
  frames_.updateRotations();
  mb_->compTreeLinkVelocities(frames_.omega_.data(), frames_.vel_.data());
}

LinkFrames BulletBody::currentFrames() const {
  const btMultiBody& m = *mb_;
  const int n = m.getNumLinks();
  LinkFrames f;
  f.resize(n + 1);
  multiBodyFrames(m, f.world_to_local_, f.local_origin_);
  f.updateRotations();
  m.compTreeLinkVelocities(f.omega_.data(), f.vel_.data());
  return f;
}

void BulletBody::framesAfterStep() {
  // Bullet's step placed the links (and joints moved since have their caches from
  // setJointPos); after a lean step, the same sums without writing the multibody.
  if (world().leanStepped()) {
    multiBodyFrames(*mb_, frames_.world_to_local_, frames_.local_origin_);
  } else {
    mb_->forwardKinematics(frames_.world_to_local_, frames_.local_origin_);
  }
  frames_.updateRotations();
  mb_->compTreeLinkVelocities(frames_.omega_.data(), frames_.vel_.data());
}

void BulletBody::setRotations(const TreeDynamics& tree) {
  frames_.world_to_local_ = tree.worldToLocal();
  frames_.rotation_ = tree.rotations();
}

void BulletBody::setFrame(int k, const btVector3& origin, const btVector3& omega,
                          const btVector3& velocity) {
  frames_.local_origin_[k] = origin;
  frames_.omega_[k] = omega;
  frames_.vel_[k] = velocity;
}

void BulletBody::settle() {
  updateKinematics();
  ServoWorld& w = world();
  w.placeColliders();
  for (auto& col : colliders_) {
    w.updateSingleAabb(col.get());
    if (col->getBroadphaseHandle()) {
      w.getBroadphase()->getOverlappingPairCache()->cleanProxyFromPairs(col->getBroadphaseHandle(),
                                                                        w.getDispatcher());
    }
  }
}

bool BulletBody::mayTouch() const {
  if (!scene_->hasGround()) return false;
  if (scene_->hasContacts()) return true;
  constexpr double kClearance = 0.1;  // m: well beyond Bullet's contact margins
  const double dt = scene_->timeStep();
  const LinkFrames& f = frames_;
  for (size_t k = 0; k < reach_.size(); ++k) {
    if (reach_[k] <= 0.0) continue;
    const int i = static_cast<int>(k);
    // The travel below is at most 2 dt sqrt(2 (v^2 + (w reach)^2)): well clear of that (as
    // high in the air), no square roots.
    const double margin = f.com(i).z() - reach_[k] - kClearance;
    const double w_reach = f.omega(i).length2() * reach_[k] * reach_[k];
    if (margin > 0.0 &&
        8.0 * dt * dt * (f.velocity(i).length2() + w_reach) < 0.99 * margin * margin) {
      continue;
    }
    const double travel = 2.0 * dt * (f.velocity(i).length() + f.omega(i).length() * reach_[k]);
    if (f.com(i).z() - reach_[k] - travel < kClearance) return true;
  }
  return false;
}

std::string BulletBody::motionFault(double max_speed) const {
  const LinkFrames& f = frames_;
  const CreatureModel& m = model_;
  for (size_t k = 0; k < m.links.size(); ++k) {
    const int i = static_cast<int>(k);
    // Named only on a fault: this runs every step.
    auto link = [&m, k] { return "link '" + m.links[k].name + "'"; };
    const btQuaternion& q = f.worldToLink(i);
    if (!std::isfinite(f.com(i).x() + f.com(i).y() + f.com(i).z()) ||
        !std::isfinite(q.x() + q.y() + q.z() + q.w())) {
      return link() + " has a non-finite pose";
    }
    // The fastest point of the link: its COM's speed plus the spin times its reach, at most
    // the square root of 2 (v^2 + (w reach)^2): well below the limit (as almost always), no
    // square roots.
    const double v2 = f.velocity(i).length2(), w2r2 = f.omega(i).length2() * reach_[k] * reach_[k];
    if (max_speed > 0.0 && 2.0 * (v2 + w2r2) < 0.99 * max_speed * max_speed) continue;
    const double v = f.velocity(i).length(), w = f.omega(i).length();
    if (!std::isfinite(v) || !std::isfinite(w)) return link() + " has a non-finite velocity";
    const double speed = v + w * reach_[k];
    if (speed > max_speed) {
      std::ostringstream msg;
      msg.precision(4);
      msg << link() << " moves at " << speed << " m/s (max_speed " << max_speed << " m/s)";
      return msg.str();
    }
  }
  return {};  // no fault (an empty string without copying a literal)
}

}  // namespace flapsim
