// The Bullet scene of one creature: its dynamics world (stepped in phases, with the ground
// check), the serialised Dantzig LCP solver, the ground, and conversions to and from Bullet.
// Private to flapsim_core.
#pragma once

#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/MLCPSolvers/btDantzigSolver.h>
#include <btBulletDynamicsCommon.h>

#include <functional>
#include <memory>
#include <utility>

#include "dynamics/tree_dynamics.h"
#include "flapsim/types.h"
#include "flapsim/world.h"

namespace flapsim {

class JointLimits;

inline btVector3 toBt(const Vec3& v) { return btVector3(v.x(), v.y(), v.z()); }
inline btQuaternion toBt(const Quat& q) { return btQuaternion(q.x(), q.y(), q.z(), q.w()); }
inline btTransform toBt(const Pose& p) {
  return btTransform(toBt(p.orientation), toBt(p.position));
}
inline Vec3 fromBt(const btVector3& v) { return Vec3(v.x(), v.y(), v.z()); }
inline Quat fromBt(const btQuaternion& q) { return Quat(q.w(), q.x(), q.y(), q.z()); }
// btMultiBody::getJointVel(link) of a one-dof joint, inline (Bullet's is not).
inline btScalar jointVel(const btMultiBody& mb, int link) {
  return mb.getVelocityVector()[6 + mb.getLink(link).m_dofOffset];
}

// The world frames of a multibody's links at its current positions (index 0: the base,
// k + 1: link k), by btMultiBody::forwardKinematics' arithmetic but without writing the
// multibody's cached link transforms.
void multiBodyFrames(const btMultiBody& mb, btAlignedObjectArray<btQuaternion>& world_to_local,
                     btAlignedObjectArray<btVector3>& local_origin);

// A multibody world whose step is taken in phases, so that the creature's servo stage acts
// between Bullet's unconstrained velocity update (gravity, air, damping) and its constraint
// solve (limits, contacts), which is where Bullet's own joint motors act:
//
//   beginStep(h)   the unconstrained velocities: Bullet's step up to the end of its external
//                  forces (collision detection included), or a lean step's velocity update
//   (the caller)   ServoStage::solve, with leanTree()
//   constrain()    joint limits and contacts: Bullet's constraint solve (a lean step: only if
//                  a joint limit may act)
//   integrate()    positions from the velocities, and Bullet's end of step
//
// Together, with nothing between them, what stepSimulation(h, 0, h) does (without Bullet's
// profiler), with the same results up to the rounding of the lean step's velocity update.
class ServoWorld : public btMultiBodyDynamicsWorld {
 public:
  using btMultiBodyDynamicsWorld::btMultiBodyDynamicsWorld;
  // `may_touch` answers false while the creature cannot touch anything this step; collision
  // detection (bounding boxes, broadphase, narrowphase) is then skipped: it would find nothing.
  void setGroundCheck(std::function<bool()> may_touch) { may_touch_ = std::move(may_touch); }

  // Lean steps (on by default) take a step in which nothing can touch from the multibody's
  // own routines and TreeDynamics; off, every step is Bullet's.
  void setLeanSteps(bool on) { lean_ = on; }

  // The phases of one step of `h`, in this order (else std::logic_error). beginStep() returns
  // whether the step moves anything (Bullet takes no step of a length it rounds to zero): if
  // not, no stage acts before constrain().
  bool beginStep(btScalar h);
  void constrain();
  void integrate();
  // Whether the last step was a lean step (whose colliders stay behind).
  bool leanStepped() const { return lean_stepped_; }
  // Whether a joint limit may have acted in the last constrain() (contacts: BulletBody's).
  bool constraintsSolved() const { return solved_; }
  // Between beginStep() and constrain() of a lean step: its velocity update's tree (inertias
  // and joint subspaces of the step's positions); else null.
  // Its velocity update may still be to come (TreeDynamics::velocitiesPending()): the servo
  // stage then takes it into its own solve.
  TreeDynamics* leanTree() { return tree_fresh_ ? &tree_ : nullptr; }
  // The tree the lean steps use, for the frames and velocities of the multibody between
  // steps (TreeDynamics::updateFrames() and velocities()).
  TreeDynamics& tree() { return tree_; }
  // Puts the colliders where the multibody now is (after its state was set between steps,
  // and before the first full step after lean ones).
  void placeColliders();

  void performDiscreteCollisionDetection() override;

 private:
  enum class Phase { kIdle, kVelocities, kConstrained };
  // Whether the world holds what a lean step handles: one multibody that never sleeps, its
  // constraints our joint limits, nothing else that moves or acts, no callbacks.
  bool leanCapable(btScalar h) const;
  // Whether a multibody constraint could have rows this step (one we do not know: yes).
  bool constraintsMayAct(btScalar h) const;
  // Bullet's step (btDiscreteDynamicsWorld::stepSimulation and internalSingleStepSimulation,
  // btMultiBodyDynamicsWorld::solveConstraints) in the three phases.
  void beginFullStep(btScalar h);
  void integrateFullStep();
  // A lean step: Bullet's step without the work that finds nothing while no contact is
  // possible: the interpolated transforms (overwritten before anything reads them), collision
  // detection (skipped anyway), islands and the constraint solver, unless a joint limit may
  // act. The unconstrained velocities come from TreeDynamics where it handles the multibody.
  void beginLeanStep(btScalar h);
  void constrainLeanStep();
  void integrateLeanStep();
  // The rest of Bullet's velocity stage once the servos acted: islands, the solve of all
  // constraints and contacts, and the solver's velocity change.
  void solveConstraintsAfterServos(btContactSolverInfo& info);
  // A lean step's limit solve: first with rows for the joints near a bound only, again with
  // every row if that sent another joint towards its bound (joint_limit.h).
  void solveLimitsNearFirst(btMultiBody& mb, btContactSolverInfo& info);
  // Bullet's articulated-body pass: velocities += h * accelerations, and its solver caches.
  void bulletVelocityStep(btMultiBody& mb, btScalar h, const btContactSolverInfo& info);
  std::function<bool()> may_touch_;
  bool lean_ = true;
  std::vector<JointLimits*> limits_;  // solveLimitsNearFirst's scratch: the limits,
  std::vector<btScalar> velocities_;  // and the velocities before its first solve
  TreeDynamics tree_;                 // the lean step's velocity update
  bool tree_fresh_ = false;
  // Lean steps leave the colliders behind (only collision detection reads them); the next
  // full step first places them where the multibody is then.
  bool colliders_behind_ = false;
  bool lean_stepped_ = false;
  bool solved_ = false;  // constraintsSolved()
  // The step under way: its phase, length, whether it moves anything, and whether a lean
  // step's velocity update is TreeDynamics'.
  Phase phase_ = Phase::kIdle;
  btScalar step_ = 0;
  bool moves_ = false;
  bool lean_tree_ = false;
};

// Bullet's Dantzig LCP keeps its failure flag in a global variable (s_error in
// btDantzigLCP.cpp), so two solves at once in different threads can fail each other and
// fall back to another solver. One solve at a time keeps parallel runs bit-identical to
// serial ones; the rest of the step still runs in parallel.
class SerialDantzigSolver : public btDantzigSolver {
 public:
  bool solveMLCP(const btMatrixXu& A, const btVectorXu& b, btVectorXu& x, const btVectorXu& lo,
                 const btVectorXu& hi, const btAlignedObjectArray<int>& limit_dependency,
                 int iterations, bool use_sparsity) override;
};

// A Bullet world of its own for each creature: creatures do not touch one another, so
// they can be stepped in parallel, and adding one never perturbs another's trajectory.
class Scene {
 public:
  explicit Scene(const WorldParams& params);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  ServoWorld& world() const { return *world_; }
  bool hasGround() const { return ground_ != nullptr; }
  // Whether the last collision detection left any contact manifold.
  bool hasContacts() const { return dispatcher_->getNumManifolds() > 0; }
  double timeStep() const { return world_->getSolverInfo().m_timeStep; }

 private:
  void addGround(const WorldParams& params);

  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<SerialDantzigSolver> lcp_;
  std::unique_ptr<btMultiBodyConstraintSolver> solver_;
  std::unique_ptr<ServoWorld> world_;
  std::unique_ptr<btCollisionShape> ground_shape_;
  std::unique_ptr<btCollisionObject> ground_;
};

}  // namespace flapsim
