#include "flapsim/world.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <BulletDynamics/Featherstone/btMultiBodyMLCPConstraintSolver.h>
#include <BulletDynamics/MLCPSolvers/btDantzigSolver.h>
#include <btBulletDynamicsCommon.h>

#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <sstream>
#include <thread>
#include <utility>

#include "flapsim/joint_servo.h"

namespace flapsim {

namespace {

btVector3 toBt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
btQuaternion toBt(const Quat& q) { return btQuaternion(q.x(), q.y(), q.z(), q.w()); }
btTransform toBt(const Pose& p) { return btTransform(toBt(p.orientation), toBt(p.position)); }
Vec3 fromBt(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }
Quat fromBt(const btQuaternion& q) { return Quat(q.w(), q.x(), q.y(), q.z()); }

bool finite(const Vec3& v) { return v.allFinite(); }
bool finite(const Pose& p) { return p.position.allFinite() && p.orientation.coeffs().allFinite(); }

std::string checkAir(const AirParams& a) {
  if (!std::isfinite(a.density) || a.density < 0.0) return "air density must be finite and >= 0";
  if (!std::isfinite(a.drag_coefficient) || a.drag_coefficient < 0.0) {
    return "air drag_coefficient must be finite and >= 0";
  }
  if (!finite(a.wind)) return "air wind must be finite";
  if (!makeAirModel(a.model)) return "unknown air model '" + a.model + "' (pressure, quasi_steady)";
  if (a.subdivisions_u < 1 || a.subdivisions_v < 1 || a.subdivisions_u > 1000 ||
      a.subdivisions_v > 1000) {
    return "air subdivisions must be in 1..1000";
  }
  return "";
}

// Cells (in the COM frame), drag coefficient and volume of a link's boxes.
AeroSurface linkSurface(const LinkModel& l, const AirParams& air) {
  AeroSurface surface;
  const int nu = l.aero.subdivisions_u > 0 ? l.aero.subdivisions_u : air.subdivisions_u;
  const int nv = l.aero.subdivisions_v > 0 ? l.aero.subdivisions_v : air.subdivisions_v;
  const Pose com_inv{-l.com, Quat::Identity()};
  for (const Box& b : l.boxes) appendBox(surface, b.size, com_inv * b.origin, nu, nv);
  surface.drag_coefficient =
      l.aero.drag_coefficient ? *l.aero.drag_coefficient : air.drag_coefficient;
  return surface;
}

// A multibody world that lets its creature's joint servos act between Bullet's
// unconstrained velocity update (gravity, air, damping) and its constraint solve (limits,
// contacts), which is where Bullet's own joint motors act.
class ServoWorld : public btMultiBodyDynamicsWorld {
 public:
  using btMultiBodyDynamicsWorld::btMultiBodyDynamicsWorld;
  void setServos(std::function<void()> servos) { servos_ = std::move(servos); }
  // `may_touch` answers false while the creature cannot touch anything this step; collision
  // detection (bounding boxes, broadphase, narrowphase) is then skipped: it would find nothing.
  void setGroundCheck(std::function<bool()> may_touch) { may_touch_ = std::move(may_touch); }

  void performDiscreteCollisionDetection() override {
    if (may_touch_ && !may_touch_()) return;
    btMultiBodyDynamicsWorld::performDiscreteCollisionDetection();
  }

 protected:
  void solveExternalForces(btContactSolverInfo& info) override {
    btMultiBodyDynamicsWorld::solveExternalForces(info);
    if (servos_) servos_();
  }

 private:
  std::function<void()> servos_;
  std::function<bool()> may_touch_;
};

// Joint damping is applied as an explicit torque -d qdot, stable while d dt stays well
// under the joint's inertia. Beyond that it is capped at a quarter of the child link's own
// inertia about the axis per step: the joint is then nearly rigid in velocity either way,
// and a large URDF damping cannot make the step blow up.
double dampingLimit(const CreatureModel& m, const JointModel& j, double dt) {
  const LinkModel& child = m.links[j.child_link];
  if (j.type == JointType::kPrismatic) return 0.25 * child.mass / dt;
  const Vec3 r = child.com - child.com.dot(j.axis) * j.axis;  // COM off the axis
  const double inertia = child.inertia.dot(j.axis.cwiseAbs2()) + child.mass * r.squaredNorm();
  return 0.25 * inertia / dt;
}

// Time constant of the feathering servo.
constexpr double kFeatherTime = 0.005;

// How a movable joint is driven this step.
struct JointDrive {
  enum class Mode { kPassive, kStroke, kVelocity };
  Mode mode = Mode::kPassive;
  StrokeGenerator stroke;
  double velocity = 0.0;
};

struct AeroBody {
  int link = 0;       // model link index (0 = root = Bullet base)
  std::string model;  // the link's own air model, empty for the world's
  AeroSurface surface;
  bool enabled = true;
  LinkAero last;
};

// What the user asked for: enough to rebuild a creature bit-for-bit.
struct CreatureRecord {
  std::string name;
  CreatureModelPtr model;
  Pose pose;
  Twist twist;
  std::vector<JointDrive> drives;  // per model joint
};

// Bullet's Dantzig LCP keeps its failure flag in a global variable (s_error in
// btDantzigLCP.cpp), so two solves at once in different threads can fail each other and
// fall back to another solver. One solve at a time keeps parallel runs bit-identical to
// serial ones; the rest of the step still runs in parallel.
class SerialDantzigSolver : public btDantzigSolver {
 public:
  bool solveMLCP(const btMatrixXu& A, const btVectorXu& b, btVectorXu& x, const btVectorXu& lo,
                 const btVectorXu& hi, const btAlignedObjectArray<int>& limit_dependency,
                 int iterations, bool use_sparsity) override {
    // A spin lock: the solves are short (microseconds), sleeping on a mutex costs more.
    static std::atomic_flag busy = ATOMIC_FLAG_INIT;
    while (busy.test_and_set(std::memory_order_acquire)) {
    }
    const bool ok =
        btDantzigSolver::solveMLCP(A, b, x, lo, hi, limit_dependency, iterations, use_sparsity);
    busy.clear(std::memory_order_release);
    return ok;
  }
};

// A Bullet world of its own for each creature: creatures do not touch one another, so
// they can be stepped in parallel, and adding one never perturbs another's trajectory.
struct Scene {
  explicit Scene(const WorldParams& params) {
    btDefaultCollisionConstructionInfo info;
    info.m_defaultMaxPersistentManifoldPoolSize = 64;  // small pools: many scenes
    info.m_defaultMaxCollisionAlgorithmPoolSize = 64;
    config = std::make_unique<btDefaultCollisionConfiguration>(info);
    dispatcher = std::make_unique<btCollisionDispatcher>(config.get());
    broadphase = std::make_unique<btDbvtBroadphase>();
    // A direct (Dantzig) LCP solve of all joint limits and contacts at once: sequential
    // impulses would serve the left wing's limit before the right's and break the
    // left/right symmetry of a flapping unit.
    lcp = std::make_unique<SerialDantzigSolver>();
    solver = std::make_unique<btMultiBodyMLCPConstraintSolver>(lcp.get());
    world = std::make_unique<ServoWorld>(dispatcher.get(), broadphase.get(), solver.get(),
                                         config.get());
    world->setGravity(toBt(params.gravity));
    world->getSolverInfo().m_numIterations = params.solver_iterations;
    world->getDispatchInfo().m_deterministicOverlappingPairs = true;
    if (params.ground) {
      // A large flat box rather than an infinite plane: its finite bounding box lets the
      // broadphase skip all contact work while the creature is in the air.
      const btScalar half = 1000.0, depth = 1.0;
      ground_shape = std::make_unique<btBoxShape>(btVector3(half, half, depth));
      ground = std::make_unique<btCollisionObject>();
      ground->setCollisionShape(ground_shape.get());
      ground->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0, -depth)));
      ground->setFriction(params.ground_friction);
      world->addCollisionObject(ground.get());
    }
  }
  ~Scene() {
    if (ground) world->removeCollisionObject(ground.get());
  }

  std::unique_ptr<btDefaultCollisionConfiguration> config;
  std::unique_ptr<btCollisionDispatcher> dispatcher;
  std::unique_ptr<btBroadphaseInterface> broadphase;
  std::unique_ptr<SerialDantzigSolver> lcp;
  std::unique_ptr<btMultiBodyConstraintSolver> solver;
  std::unique_ptr<ServoWorld> world;
  std::unique_ptr<btCollisionShape> ground_shape;
  std::unique_ptr<btCollisionObject> ground;
};

// The Bullet side of a creature.
struct CreatureBody {
  ~CreatureBody() {
    if (!scene) return;
    btMultiBodyDynamicsWorld* world = scene->world.get();
    for (auto& l : limits) world->removeMultiBodyConstraint(l.get());
    for (auto& c : colliders) world->removeCollisionObject(c.get());
    if (mb) world->removeMultiBody(mb.get());
  }

  // Refreshes the link frames and velocities below from the multibody's state.
  void updateKinematics() {
    mb->forwardKinematics(world_to_local, local_origin);
    mb->compTreeLinkVelocities(omega.data(), vel.data());
  }
  // World-frame kinematics of link k's centre of mass (after updateKinematics).
  BodyKinematics kinematics(int k) const {
    const btQuaternion to_world = world_to_local[k].inverse();
    BodyKinematics kin;
    kin.orientation = fromBt(to_world);
    kin.com = fromBt(local_origin[k]);
    kin.linear_velocity = fromBt(quatRotate(to_world, vel[k]));
    kin.angular_velocity = fromBt(quatRotate(to_world, omega[k]));
    return kin;
  }

  // Whether a link could come within reach of the ground in this step (the link frames are
  // those of updateKinematics() at the start of the step). Creatures do not collide with
  // themselves, so without ground, or well above it, there is nothing to detect.
  bool mayTouch() const {
    if (!scene->ground) return false;
    if (scene->dispatcher->getNumManifolds() > 0) return true;
    constexpr double kClearance = 0.1;  // m: well beyond Bullet's contact margins
    const double dt = scene->world->getSolverInfo().m_timeStep;
    for (size_t k = 0; k < reach.size(); ++k) {
      if (reach[k] <= 0.0) continue;
      const double travel = 2.0 * dt * (vel[k].length() + omega[k].length() * reach[k]);
      if (local_origin[static_cast<int>(k)].z() - reach[k] - travel < kClearance) return true;
    }
    return false;
  }

  // Called by Bullet once the velocities hold gravity, air and damping for this step:
  // solves every servo together and adds the velocity change it causes. The link frames
  // are those of updateKinematics() at the start of the step (positions have not moved).
  void applyServos() {
    const CreatureModel& m = *model;
    bool any = false;
    for (size_t k = 1; k < demands.size(); ++k) {
      if (!demands[k].active) continue;
      demands[k].velocity_change = servo_target[k] - mb->getJointVel(static_cast<int>(k) - 1);
      any = true;
    }
    if (!any) {
      solution.impulse.assign(demands.size(), 0.0);
      return;
    }
    const btVector3 origin = local_origin[0];  // the root's COM
    for (size_t k = 0; k < servo_links.size(); ++k) {
      const LinkModel& l = m.links[k];
      ServoLink& s = servo_links[k];
      const btMatrix3x3 rot(world_to_local[k].inverse());
      const btMatrix3x3 inertia = rot.scaled(toBt(l.inertia)) * rot.transpose();
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) s.inertia(r, c) = inertia[r][c];
      }
      s.com = fromBt(local_origin[k] - origin);
      if (k > 0) {
        const JointModel& j = m.joints[l.parent_joint];
        s.axis = fromBt(rot * toBt(j.axis));
        s.anchor = fromBt(local_origin[k] - rot * toBt(l.com) - origin);
      }
    }
    servo.solve(servo_links, m.fixed_base, demands, solution);
    for (size_t k = 1; k < demands.size(); ++k) {
      if (servo_links[k].joint == ServoJointType::kFixed) continue;
      const int link = static_cast<int>(k) - 1;
      mb->setJointVel(link, mb->getJointVel(link) + solution.velocity_change[k]);
    }
    if (!m.fixed_base) {
      const Vec6& dv = solution.root_velocity_change;
      mb->setBaseOmega(mb->getBaseOmega() + toBt(Vec3(dv.head<3>())));
      mb->setBaseVel(mb->getBaseVel() + toBt(Vec3(dv.tail<3>())));
    }
  }

  std::unique_ptr<Scene> scene;  // declared first: destroyed last
  std::unique_ptr<btMultiBody> mb;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> limits;
  // Per model link: distance from its COM to the farthest corner of its boxes (0 if none).
  std::vector<double> reach;
  std::vector<double> max_effort;  // per model joint
  std::vector<double> damping;     // per model joint: URDF damping, capped for stability
  // Joint servos (wing motors, velocity targets, feathering, Coulomb friction), indexed
  // by model link: the servo of the joint to that link's parent.
  const CreatureModel* model = nullptr;
  std::vector<double> servo_target;  // joint velocity wanted at the end of the step
  std::vector<ServoDemand> demands;
  std::vector<ServoLink> servo_links;
  JointServoSolver servo;
  ServoSolution solution;  // of the last step; impulses all zero if no servo acted
  std::vector<AeroBody> aero;
  btAlignedObjectArray<btQuaternion> world_to_local;
  btAlignedObjectArray<btVector3> local_origin;
  std::vector<btVector3> omega, vel;
};

}  // namespace

std::string validateWorldParams(const WorldParams& p) {
  if (!std::isfinite(p.step_size) || p.step_size <= 0.0 || p.step_size > 0.1) {
    return "step_size must be in (0, 0.1] s";
  }
  if (!finite(p.gravity)) return "gravity must be finite";
  if (!std::isfinite(p.ground_friction) || p.ground_friction < 0.0) {
    return "ground_friction must be >= 0";
  }
  if (p.solver_iterations < 1) return "solver_iterations must be >= 1";
  if (p.threads < 1 || p.threads > 256) return "threads must be in 1..256";
  if (!std::isfinite(p.default_wing_effort) || p.default_wing_effort <= 0.0) {
    return "default_wing_effort must be > 0";
  }
  return checkAir(p.air);
}

class World::Impl {
 public:
  explicit Impl(const WorldParams& p) : params_(p), air_model_(makeAirModel(p.air.model)) {
    for (const char* name : {"pressure", "quasi_steady"}) named_models_[name] = makeAirModel(name);
    build();
  }
  ~Impl() { teardown(); }

  // ---- Bullet world lifetime ---------------------------------------------------
  void build() {
    bodies_.clear();
    for (const auto& r : records_) bodies_.push_back(makeBody(r));
    time_steps_ = 0;
  }

  void teardown() { bodies_.clear(); }

  std::unique_ptr<CreatureBody> makeBody(const CreatureRecord& r) {
    const CreatureModel& m = *r.model;
    auto body = std::make_unique<CreatureBody>();
    body->scene = std::make_unique<Scene>(params_);
    btMultiBodyDynamicsWorld* world = body->scene->world.get();
    const int n = static_cast<int>(m.links.size()) - 1;
    const LinkModel& root = m.links[0];
    body->mb = std::make_unique<btMultiBody>(n, root.mass, toBt(root.inertia), m.fixed_base, false);
    btMultiBody* mb = body->mb.get();
    for (int k = 1; k <= n; ++k) {
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
          mb->setupRevolute(k - 1, l.mass, toBt(l.inertia), parent, rot, toBt(j.axis),
                            parent_com_to_pivot, pivot_to_com, true);
          break;
        case JointType::kPrismatic:
          mb->setupPrismatic(k - 1, l.mass, toBt(l.inertia), parent, rot, toBt(j.axis),
                             parent_com_to_pivot, pivot_to_com, true);
          break;
        case JointType::kFixed:
          mb->setupFixed(k - 1, l.mass, toBt(l.inertia), parent, rot, parent_com_to_pivot,
                         pivot_to_com);
          break;
      }
    }
    mb->finalizeMultiDof();
    mb->setLinearDamping(0);
    mb->setAngularDamping(0);
    mb->setMaxCoordinateVelocity(1e6);
    mb->setMaxAppliedImpulse(1e6);
    mb->setHasSelfCollision(false);
    mb->setUseGyroTerm(true);
    mb->setCanSleep(false);
    const Pose com_pose = r.pose * Pose{root.com, Quat::Identity()};
    mb->setBaseWorldTransform(toBt(com_pose));
    mb->setBaseVel(toBt(r.twist.linear));
    mb->setBaseOmega(toBt(r.twist.angular));
    world->addMultiBody(mb);

    body->world_to_local.resize(n + 1);
    body->local_origin.resize(n + 1);
    body->omega.resize(n + 1);
    body->vel.resize(n + 1);
    mb->forwardKinematics(body->world_to_local, body->local_origin);

    // Collision shapes (boxes, in the COM frame) and aero surfaces.
    body->reach.assign(n + 1, 0.0);
    for (int k = 0; k <= n; ++k) {
      const LinkModel& l = m.links[k];
      const Pose com_inv{-l.com, Quat::Identity()};
      for (const Box& b : l.boxes) {
        const double corner = (com_inv * b.origin).position.norm() + 0.5 * b.size.norm();
        body->reach[k] = std::max(body->reach[k], corner);
      }
      if (!l.boxes.empty()) {
        btCollisionShape* shape = nullptr;
        const Pose first = com_inv * l.boxes[0].origin;
        if (l.boxes.size() == 1 && first.position.isZero(1e-12) &&
            first.orientation.isApprox(Quat::Identity(), 1e-12)) {
          // One box centred on the COM: no compound needed (cheaper contact tests).
          body->shapes.push_back(std::make_unique<btBoxShape>(toBt(0.5 * l.boxes[0].size)));
          shape = body->shapes.back().get();
        } else {
          auto compound =
              std::make_unique<btCompoundShape>(false, static_cast<int>(l.boxes.size()));
          for (const Box& b : l.boxes) {
            auto box = std::make_unique<btBoxShape>(toBt(0.5 * b.size));
            compound->addChildShape(toBt(com_inv * b.origin), box.get());
            body->shapes.push_back(std::move(box));
          }
          shape = compound.get();
          body->shapes.push_back(std::move(compound));
        }
        auto col = std::make_unique<btMultiBodyLinkCollider>(mb, k - 1);
        col->setCollisionShape(shape);
        col->setFriction(params_.ground_friction);
        col->setActivationState(DISABLE_DEACTIVATION);
        btTransform tr(body->world_to_local[k].inverse(), body->local_origin[k]);
        col->setWorldTransform(tr);
        world->addCollisionObject(col.get(), btBroadphaseProxy::DefaultFilter,
                                  btBroadphaseProxy::AllFilter);
        if (k == 0) {
          mb->setBaseCollider(col.get());
        } else {
          mb->getLink(k - 1).m_collider = col.get();
        }
        body->colliders.push_back(std::move(col));
      }
      AeroBody aero;
      aero.link = k;
      aero.enabled = l.aero.enabled && !l.boxes.empty();
      aero.last.link = k;
      if (aero.enabled) {
        aero.model = l.aero.model;
        aero.surface = linkSurface(l, params_.air);
        body->aero.push_back(std::move(aero));
      }
    }

    // Joint limits (Bullet constraints) and servos (ours, see applyServos).
    body->max_effort.assign(m.joints.size(), 0.0);
    body->damping.assign(m.joints.size(), 0.0);
    for (size_t ji = 0; ji < m.joints.size(); ++ji) {
      const JointModel& j = m.joints[ji];
      if (!j.movable()) continue;
      const int link = j.child_link - 1;
      if (j.limited && j.lower < j.upper) {
        auto lim = std::make_unique<btMultiBodyJointLimitConstraint>(mb, link, j.lower, j.upper);
        world->addMultiBodyConstraint(lim.get());
        body->limits.push_back(std::move(lim));
      }
      body->max_effort[ji] = j.effort > 0.0 ? j.effort : params_.default_wing_effort;
      body->damping[ji] = std::min(j.damping, dampingLimit(m, j, params_.step_size));
    }
    body->model = &m;
    body->servo_target.assign(n + 1, 0.0);
    body->demands.assign(n + 1, ServoDemand());
    body->servo_links.resize(n + 1);
    for (int k = 0; k <= n; ++k) {
      const LinkModel& l = m.links[k];
      ServoLink& s = body->servo_links[k];
      s.mass = l.mass;
      if (k == 0) continue;
      const JointModel& j = m.joints[l.parent_joint];
      s.parent = j.parent_link;
      s.joint = j.type == JointType::kFixed       ? ServoJointType::kFixed
                : j.type == JointType::kPrismatic ? ServoJointType::kPrismatic
                                                  : ServoJointType::kRevolute;
    }
    CreatureBody* b = body.get();
    body->scene->world->setServos([b] { b->applyServos(); });
    body->scene->world->setGroundCheck([b] { return b->mayTouch(); });
    return body;
  }

  // ---- stepping ------------------------------------------------------------------
  void applyDrives(CreatureRecord& r, CreatureBody& b) {
    const CreatureModel& m = *r.model;
    btMultiBody* mb = b.mb.get();
    const double dt = params_.step_size;
    // A servo with target velocity `target` and torque bound `effort` on a joint.
    auto drive = [&b, dt](int joint_link, double target, double effort) {
      ServoDemand& demand = b.demands[joint_link];
      demand.active = true;
      demand.max_impulse = effort * dt;
      b.servo_target[joint_link] = target;
    };
    for (size_t ji = 0; ji < m.joints.size(); ++ji) {
      const JointModel& j = m.joints[ji];
      if (!j.movable()) continue;
      const int link = j.child_link - 1;
      JointDrive& d = r.drives[ji];
      b.demands[j.child_link].active = false;
      switch (d.mode) {
        case JointDrive::Mode::kStroke:
          drive(j.child_link, d.stroke.target(mb->getJointPos(link)), b.max_effort[ji]);
          break;
        case JointDrive::Mode::kVelocity:
          drive(j.child_link, d.velocity, b.max_effort[ji]);
          break;
        case JointDrive::Mode::kPassive:
          // Coulomb friction: a zero-velocity servo whose torque is capped by friction.
          if (j.friction > 0.0) drive(j.child_link, 0.0, j.friction);
          if (b.damping[ji] > 0.0) {
            mb->addJointTorque(link, -b.damping[ji] * mb->getJointVel(link));
          }
          break;
      }
    }
    // Feathering: a stroking wing pitches its feather joint to the commanded angle during
    // the upstroke and back to flat for the downstroke (a stiff position servo).
    for (int wi : m.wing_joints) {
      const JointModel& wing = m.joints[wi];
      const JointDrive& d = r.drives[wi];
      if (wing.feather_joint < 0 || d.mode != JointDrive::Mode::kStroke) continue;
      const JointModel& feather = m.joints[wing.feather_joint];
      const double target =
          d.stroke.phase() == StrokeGenerator::Phase::kUp ? d.stroke.command().feather : 0.0;
      drive(feather.child_link, (target - mb->getJointPos(feather.child_link - 1)) / kFeatherTime,
            b.max_effort[wing.feather_joint]);
    }
  }

  void applyAir(CreatureBody& b) {
    btMultiBody* mb = b.mb.get();
    const AirParams& air = params_.air;
    for (AeroBody& a : b.aero) {
      const int k = a.link;
      const BodyKinematics kin = b.kinematics(k);
      const AirModel& model = a.model.empty() ? *air_model_ : *named_models_.at(a.model);
      Wrench w =
          model.bodyWrench(kin, a.surface, air, record_cells_ ? &a.last.cell_forces : nullptr);
      if (air.buoyancy) w.force += buoyancyForce(a.surface.volume, air.density, params_.gravity);
      a.last.com = kin.com;
      a.last.wrench = w;
      if (record_cells_) {
        a.last.cell_centres.resize(a.surface.cells.size());
        for (size_t i = 0; i < a.surface.cells.size(); ++i) {
          a.last.cell_centres[i] = kin.com + kin.orientation * a.surface.cells[i].centre;
        }
      }
      if (k == 0) {
        mb->addBaseForce(toBt(w.force));
        mb->addBaseTorque(toBt(w.torque));
      } else {
        mb->addLinkForce(k - 1, toBt(w.force));
        mb->addLinkTorque(k - 1, toBt(w.torque));
      }
    }
  }

  void stepOne(size_t i) {
    bodies_[i]->updateKinematics();  // for the air, the servos and the ground check
    applyDrives(records_[i], *bodies_[i]);
    if (params_.air.enabled) applyAir(*bodies_[i]);
    bodies_[i]->scene->world->stepSimulation(params_.step_size, 0, params_.step_size);
  }

  // Creatures are independent: each thread steps a contiguous share of them through all
  // `steps`, so the result does not depend on the number of threads.
  void step(int steps) {
    const size_t n = bodies_.size();
    const size_t threads = std::min<size_t>(static_cast<size_t>(params_.threads), n);
    auto run = [this, steps](size_t first, size_t last) {
      for (int s = 0; s < steps; ++s) {
        for (size_t i = first; i < last; ++i) stepOne(i);
      }
    };
    if (threads <= 1 || static_cast<size_t>(steps) * n < 64) {
      run(0, n);
    } else {
      std::vector<std::thread> pool;
      for (size_t t = 1; t < threads; ++t)
        pool.emplace_back(run, t * n / threads, (t + 1) * n / threads);
      run(0, n / threads);
      for (auto& th : pool) th.join();
    }
    time_steps_ += static_cast<std::uint64_t>(steps);
  }

  // ---- lookups -------------------------------------------------------------------
  size_t index(const std::string& name) const {
    for (size_t i = 0; i < records_.size(); ++i) {
      if (records_[i].name == name) return i;
    }
    throw InputError("unknown creature '" + name + "'");
  }

  int jointIndex(size_t c, const std::string& joint) const {
    const CreatureModel& m = *records_[c].model;
    int j = m.findJoint(joint);
    if (j < 0) throw InputError("creature '" + records_[c].name + "' has no joint '" + joint + "'");
    return j;
  }

  WorldParams params_;
  AirModelPtr air_model_;                            // the world's default
  std::map<std::string, AirModelPtr> named_models_;  // for links that name their own
  bool record_cells_ = false;
  std::vector<CreatureRecord> records_;
  std::vector<std::unique_ptr<CreatureBody>> bodies_;
  std::uint64_t time_steps_ = 0;
};

// ---- World ---------------------------------------------------------------------------

namespace {
WorldParams checked(const WorldParams& p) {
  std::string err = validateWorldParams(p);
  if (!err.empty()) throw InputError(err);
  return p;
}
}  // namespace

World::World(const WorldParams& params) : impl_(std::make_unique<Impl>(checked(params))) {}
World::~World() = default;

void World::spawn(const std::string& name, CreatureModelPtr model, const Pose& pose,
                  const Twist& twist) {
  if (name.empty()) throw InputError("creature name is empty");
  if (!model) throw InputError("creature '" + name + "': no model");
  if (has(name)) throw InputError("creature name '" + name + "' is taken");
  if (!finite(pose) || pose.orientation.norm() < 1e-9) {
    throw InputError("creature '" + name + "': pose is not finite");
  }
  if (!finite(twist.linear) || !finite(twist.angular)) {
    throw InputError("creature '" + name + "': twist is not finite");
  }
  CreatureRecord r;
  r.name = name;
  r.model = model;
  r.pose = Pose{pose.position, pose.orientation.normalized()};
  r.twist = twist;
  r.drives.resize(model->joints.size());
  auto body = impl_->makeBody(r);
  impl_->records_.push_back(std::move(r));
  impl_->bodies_.push_back(std::move(body));
}

void World::remove(const std::string& name) {
  size_t i = impl_->index(name);
  impl_->bodies_.erase(impl_->bodies_.begin() + static_cast<long>(i));
  impl_->records_.erase(impl_->records_.begin() + static_cast<long>(i));
}

bool World::has(const std::string& name) const {
  for (const auto& r : impl_->records_) {
    if (r.name == name) return true;
  }
  return false;
}

std::vector<std::string> World::creatureNames() const {
  std::vector<std::string> names;
  for (const auto& r : impl_->records_) names.push_back(r.name);
  return names;
}

CreatureModelPtr World::model(const std::string& name) const {
  return impl_->records_[impl_->index(name)].model;
}

void World::reset() {
  for (auto& r : impl_->records_) {
    for (auto& d : r.drives) d.stroke.reset();
  }
  impl_->teardown();
  impl_->build();
}

void World::step(int steps) {
  if (steps < 0) throw InputError("step count must be >= 0");
  impl_->step(steps);
}

double World::time() const {
  return static_cast<double>(impl_->time_steps_) * impl_->params_.step_size;
}
std::uint64_t World::stepCount() const { return impl_->time_steps_; }
const WorldParams& World::params() const { return impl_->params_; }

void World::setAirParams(const AirParams& air) {
  std::string err = checkAir(air);
  if (!err.empty()) throw InputError(err);
  const bool grid_changed = air.subdivisions_u != impl_->params_.air.subdivisions_u ||
                            air.subdivisions_v != impl_->params_.air.subdivisions_v ||
                            air.drag_coefficient != impl_->params_.air.drag_coefficient;
  if (air.model != impl_->params_.air.model) impl_->air_model_ = makeAirModel(air.model);
  impl_->params_.air = air;
  if (grid_changed) {
    // Rebuild the aero surfaces of every creature, keeping its motion state.
    for (size_t i = 0; i < impl_->records_.size(); ++i) {
      const CreatureModel& m = *impl_->records_[i].model;
      for (AeroBody& a : impl_->bodies_[i]->aero) a.surface = linkSurface(m.links[a.link], air);
    }
  }
}

void World::setAirModel(AirModelPtr model) {
  if (!model) throw InputError("air model is null");
  impl_->air_model_ = std::move(model);
}

std::vector<int> checkWingCommands(const CreatureModel& model,
                                   const std::vector<std::string>& joints,
                                   const std::vector<StrokeCommand>& commands) {
  std::vector<int> targets;
  if (joints.empty()) {
    targets = model.wing_joints;
  } else {
    for (const std::string& name : joints) {
      const int j = model.findJoint(name);
      if (j < 0) throw InputError("no joint '" + name + "'");
      if (!model.joints[j].wing) throw InputError("joint '" + name + "' is not a wing joint");
      targets.push_back(j);
    }
  }
  if (targets.size() != commands.size()) {
    throw InputError(std::to_string(commands.size()) + " commands for " +
                     std::to_string(targets.size()) + " wing joints");
  }
  for (size_t i = 0; i < commands.size(); ++i) {
    const JointModel& j = model.joints[targets[i]];
    const std::string err = validateStroke(commands[i]);
    if (!err.empty()) throw InputError("joint '" + j.name + "': " + err);
    // The stroke turns where the wing reaches -amplitude and +amplitude: beyond a limit the
    // wing would rest on its stop with the motor pushing, and never turn.
    const double amplitude = commands[i].amplitude;
    if (j.limited && j.lower < j.upper && (amplitude >= j.upper || -amplitude <= j.lower)) {
      std::ostringstream msg;
      msg << "joint '" << j.name << "': amplitude " << amplitude
          << " rad does not fit inside its limits [" << j.lower << ", " << j.upper << "]";
      throw InputError(msg.str());
    }
  }
  return targets;
}

void World::setWingCommands(const std::string& creature, const std::vector<std::string>& joints,
                            const std::vector<StrokeCommand>& commands) {
  CreatureRecord& r = impl_->records_[impl_->index(creature)];
  std::vector<int> targets;
  try {
    targets = checkWingCommands(*r.model, joints, commands);
  } catch (const InputError& e) {
    throw InputError("creature '" + creature + "': " + e.what());
  }
  for (size_t i = 0; i < commands.size(); ++i) {
    JointDrive& d = r.drives[targets[i]];
    if (d.mode != JointDrive::Mode::kStroke) {
      d.stroke.reset();
      d.mode = JointDrive::Mode::kStroke;
    }
    d.stroke.setCommand(commands[i]);
  }
}

void World::setJointVelocityTarget(const std::string& creature, const std::string& joint,
                                   double velocity) {
  const size_t c = impl_->index(creature);
  const int j = impl_->jointIndex(c, joint);
  if (!impl_->records_[c].model->joints[j].movable()) {
    throw InputError("joint '" + joint + "' of creature '" + creature + "' is fixed");
  }
  if (!std::isfinite(velocity)) throw InputError("joint '" + joint + "': velocity is not finite");
  JointDrive& d = impl_->records_[c].drives[j];
  d.mode = JointDrive::Mode::kVelocity;
  d.velocity = velocity;
}

void World::clearJointCommand(const std::string& creature, const std::string& joint) {
  const size_t c = impl_->index(creature);
  const int j = impl_->jointIndex(c, joint);
  impl_->records_[c].drives[j] = JointDrive();
}

StrokeCommand World::wingCommand(const std::string& creature, const std::string& joint) const {
  const size_t c = impl_->index(creature);
  const JointDrive& d = impl_->records_[c].drives[impl_->jointIndex(c, joint)];
  return d.mode == JointDrive::Mode::kStroke ? d.stroke.command() : StrokeCommand();
}

CreatureState World::state(const std::string& creature) const {
  const size_t c = impl_->index(creature);
  const CreatureModel& m = *impl_->records_[c].model;
  CreatureBody& b = *impl_->bodies_[c];
  btMultiBody* mb = b.mb.get();
  b.updateKinematics();
  CreatureState s;
  const size_t n = m.links.size();
  s.link_poses.resize(n);
  s.link_twists.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const BodyKinematics kin = b.kinematics(static_cast<int>(k));
    const Quat q = kin.orientation.normalized();
    const Vec3 origin = kin.com - q * m.links[k].com;
    s.link_poses[k] = Pose{origin, q};
    s.link_twists[k] = Twist{kin.linear_velocity + kin.angular_velocity.cross(origin - kin.com),
                             kin.angular_velocity};
  }
  s.joint_positions.assign(m.joints.size(), 0.0);
  s.joint_velocities.assign(m.joints.size(), 0.0);
  s.joint_efforts.assign(m.joints.size(), 0.0);
  const std::vector<double>& impulse = b.solution.impulse;
  for (size_t j = 0; j < m.joints.size(); ++j) {
    if (!m.joints[j].movable()) continue;
    const int k = m.joints[j].child_link;
    s.joint_positions[j] = mb->getJointPos(k - 1);
    s.joint_velocities[j] = mb->getJointVel(k - 1);
    if (static_cast<size_t>(k) < impulse.size()) {
      s.joint_efforts[j] = impulse[k] / impl_->params_.step_size;
    }
  }
  return s;
}

Pose World::rootPose(const std::string& creature) const { return state(creature).link_poses[0]; }
Twist World::rootTwist(const std::string& creature) const { return state(creature).link_twists[0]; }

void World::setRecordCellForces(bool on) { impl_->record_cells_ = on; }

std::vector<LinkAero> World::aeroForces(const std::string& creature) const {
  const size_t c = impl_->index(creature);
  std::vector<LinkAero> out;
  for (const AeroBody& a : impl_->bodies_[c]->aero) out.push_back(a.last);
  return out;
}

}  // namespace flapsim
