#include "dynamics/bullet_scene.h"

#include <BulletDynamics/Featherstone/btMultiBodyInplaceSolverIslandCallback.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <BulletDynamics/Featherstone/btMultiBodyMLCPConstraintSolver.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <typeinfo>

#include "dynamics/joint_limit.h"

namespace flapsim {

void ServoWorld::performDiscreteCollisionDetection() {
  if (may_touch_ && !may_touch_()) return;
  btMultiBodyDynamicsWorld::performDiscreteCollisionDetection();
}

void multiBodyFrames(const btMultiBody& mb, btAlignedObjectArray<btQuaternion>& world_to_local,
                     btAlignedObjectArray<btVector3>& local_origin) {
  const int n = mb.getNumLinks();
  world_to_local.resize(n + 1);
  local_origin.resize(n + 1);
  world_to_local[0] = mb.getWorldToBaseRot();
  local_origin[0] = mb.getBasePos();
  for (int k = 0; k < n; ++k) {
    const int parent = mb.getParent(k);
    world_to_local[k + 1] = mb.getParentToLocalRot(k) * world_to_local[parent + 1];
    local_origin[k + 1] =
        local_origin[parent + 1] + quatRotate(world_to_local[k + 1].inverse(), mb.getRVector(k));
  }
}

namespace {

// A phase called out of order (ServoWorld::beginStep, constrain, integrate) is a logic error.
void requireOrder(bool in_order, const char* call) {
  if (!in_order) {
    throw std::logic_error(std::string("ServoWorld::") + call +
                           " out of order: a step is beginStep, constrain, integrate");
  }
}

}  // namespace

bool ServoWorld::beginStep(btScalar h) {
  requireOrder(phase_ == Phase::kIdle, "beginStep");
  phase_ = Phase::kVelocities;
  step_ = h;
  lean_stepped_ = lean_ && leanCapable(h) && may_touch_ && !may_touch_();
  if (lean_stepped_) {
    beginLeanStep(h);
  } else {
    if (colliders_behind_) placeColliders();
    beginFullStep(h);
  }
  return moves_;
}

void ServoWorld::constrain() {
  requireOrder(phase_ == Phase::kVelocities, "constrain");
  phase_ = Phase::kConstrained;
  solved_ = false;
  if (lean_stepped_) {
    constrainLeanStep();
  } else if (moves_) {
    solved_ = constraintsMayAct(step_);  // contacts: BulletBody::hasContacts()
    // solveConstraints() after solveExternalForces()
    buildIslands();
    solveInternalConstraints(getSolverInfo());
  }
}

void ServoWorld::integrate() {
  requireOrder(phase_ == Phase::kConstrained, "integrate");
  phase_ = Phase::kIdle;
  if (lean_stepped_) {
    integrateLeanStep();
  } else {
    integrateFullStep();
  }
}

// stepSimulation(h, 0, h) up to the end of solveExternalForces() within
// internalSingleStepSimulation(h).
void ServoWorld::beginFullStep(btScalar h) {
  m_localTime = m_latencyMotionStateInterpolation ? 0 : h;
  m_fixedTimeStep = 0;
  moves_ = !btFuzzyZero(h);
  if (btIDebugDraw* draw = getDebugDrawer()) {
    gDisableDeactivation = (draw->getDebugMode() & btIDebugDraw::DBG_NoDeactivation) != 0;
  }
  if (!moves_) return;
  saveKinematicState(h);
  applyGravity();
  if (m_internalPreTickCallback) (*m_internalPreTickCallback)(this, h);
  predictUnconstraintMotion(h);
  btDispatcherInfo& dispatch = getDispatchInfo();
  dispatch.m_timeStep = h;
  dispatch.m_stepCount = 0;
  dispatch.m_debugDraw = getDebugDrawer();
  createPredictiveContacts(h);
  performDiscreteCollisionDetection();
  calculateSimulationIslands();
  getSolverInfo().m_timeStep = h;
  solveExternalForces(getSolverInfo());
}

// The rest of internalSingleStepSimulation(h) and stepSimulation(h, 0, h) after the
// constraint solve.
void ServoWorld::integrateFullStep() {
  if (moves_) {
    const btScalar h = step_;
    integrateTransforms(h);
    updateActions(h);
    updateActivationState(h);
    if (m_internalTickCallback) (*m_internalTickCallback)(this, h);
  }
  synchronizeMotionStates();
  clearForces();
}

void ServoWorld::placeColliders() {
  for (int i = 0; i < m_multiBodies.size(); ++i) {
    m_multiBodies[i]->updateCollisionObjectWorldTransforms(m_scratch_world_to_local,
                                                           m_scratch_local_origin);
  }
  colliders_behind_ = false;
}

bool ServoWorld::leanCapable(btScalar h) const {
  if (m_multiBodies.size() != 1 || m_nonStaticRigidBodies.size() != 0 ||
      m_constraints.size() != 0 || m_actions.size() != 0 || m_internalPreTickCallback ||
      m_internalTickCallback || m_debugDrawer || btFuzzyZero(h)) {
    return false;
  }
  const btMultiBody& mb = *m_multiBodies[0];
  if (mb.getCanSleep() || mb.isUsingRK4Integration() || mb.isBaseKinematic()) return false;
  // Bullet skips a multibody with a sleeping collider; ours never sleep.
  if (mb.getBaseCollider() && mb.getBaseCollider()->getActivationState() != DISABLE_DEACTIVATION) {
    return false;
  }
  for (int l = 0; l < mb.getNumLinks(); ++l) {
    const btMultiBodyLinkCollider* col = mb.getLink(l).m_collider;
    if (col && col->getActivationState() != DISABLE_DEACTIVATION) return false;
  }
  return true;
}

bool ServoWorld::constraintsMayAct(btScalar h) const {
  for (int i = 0; i < m_multiBodyConstraints.size(); ++i) {
    // The exact type, not a dynamic_cast (a walk of the class hierarchy every step): anything
    // else, a class derived from JointLimits included, may act.
    const btMultiBodyConstraint* c = m_multiBodyConstraints[i];
    if (typeid(*c) != typeid(JointLimits) || static_cast<const JointLimits*>(c)->mayAct(h)) {
      return true;
    }
  }
  return false;
}

// stepSimulation(h, 0, h) for leanCapable() worlds, stage by stage (Bullet 3.24's
// btDiscreteDynamicsWorld and btMultiBodyDynamicsWorld), without the stages that change
// nothing there while no contact is possible. Its first phase: solveConstraints() up to the
// servos, the unconstrained velocities.
void ServoWorld::beginLeanStep(btScalar h) {
  btMultiBody& mb = *m_multiBodies[0];
  moves_ = true;  // leanCapable(h): h is not zero
  m_fixedTimeStep = 0;
  m_localTime = m_latencyMotionStateInterpolation ? 0 : h;
  // applyGravity(), after the forces of the step (the same sums).
  mb.addBaseForce(m_gravity * mb.getBaseMass());
  for (int l = 0; l < mb.getNumLinks(); ++l) mb.addLinkForce(l, m_gravity * mb.getLinkMass(l));
  btDispatcherInfo& dispatch = getDispatchInfo();
  dispatch.m_timeStep = h;
  dispatch.m_stepCount = 0;
  btContactSolverInfo& info = getSolverInfo();
  info.m_timeStep = h;
  mb.clearConstraintForces();
  lean_tree_ = TreeDynamics::handles(mb);
  if (lean_tree_) {
    tree_.beginStep(mb, h);  // the update itself in constrain(), unless the servos take it
  } else {
    bulletVelocityStep(mb, h, info);
  }
  mb.clearForcesAndTorques();
  tree_fresh_ = lean_tree_;
}

// The constraint solve only if a joint limit may act.
void ServoWorld::constrainLeanStep() {
  btMultiBody& mb = *m_multiBodies[0];
  btContactSolverInfo& info = getSolverInfo();
  tree_fresh_ = false;
  if (lean_tree_) tree_.finishVelocityStep(mb);
  // solveInternalConstraints(): without rows the solver changes no velocity; what remains is
  // the (zero) velocity change's clamp.
  if (constraintsMayAct(step_) || mb.internalNeedsJointFeedback()) {
    solved_ = true;
    // The solver reads the inertia caches of Bullet's own pass (no velocity change at dt 0;
    // they depend on positions only).
    if (lean_tree_) bulletVelocityStep(mb, 0, info);
    solveLimitsNearFirst(mb, info);
  } else {
    mb.processDeltaVeeMultiDof2();
  }
}

void ServoWorld::integrateLeanStep() {
  btMultiBody& mb = *m_multiBodies[0];
  const btScalar h = step_;
  // integrateMultiBodyTransforms(); the colliders wait for the next full step.
  mb.addSplitV();
  mb.stepPositionsMultiDof(h);
  colliders_behind_ = true;
  mb.substractSplitV();
  // updateActivationState(h): what it does in a leanCapable() world, without its profile
  // samples and its loops over colliders (which never sleep) and rigid bodies (none). A
  // multibody that cannot sleep is marked awake.
  mb.checkMotionAndSleepIfRequired(h);
  // clearForces() would clear the multibody's forces and torques again (beginLeanStep()
  // cleared them once it had taken them, and nothing adds any after) and those of the
  // non-static rigid bodies, which a lean world has none of.
}

void ServoWorld::bulletVelocityStep(btMultiBody& mb, btScalar h, const btContactSolverInfo& info) {
  mb.computeAccelerationsArticulatedBodyAlgorithmMultiDof(h, m_scratch_r, m_scratch_v, m_scratch_m,
                                                          false, info.m_jointFeedbackInWorldSpace,
                                                          info.m_jointFeedbackInJointFrame);
}

void ServoWorld::solveLimitsNearFirst(btMultiBody& mb, btContactSolverInfo& info) {
  limits_.clear();
  for (int i = 0; i < m_multiBodyConstraints.size(); ++i) {
    btMultiBodyConstraint* c = m_multiBodyConstraints[i];
    if (typeid(*c) == typeid(JointLimits)) limits_.push_back(static_cast<JointLimits*>(c));
  }
  if (limits_.size() != static_cast<size_t>(m_multiBodyConstraints.size()) ||
      mb.internalNeedsJointFeedback()) {
    solveConstraintsAfterServos(info);
    return;
  }
  const int n = 6 + mb.getNumDofs();
  velocities_.assign(mb.getVelocityVector(), mb.getVelocityVector() + n);
  for (JointLimits* l : limits_) l->setNearRowsOnly(true);
  solveConstraintsAfterServos(info);
  bool again = false;
  for (JointLimits* l : limits_) {
    again = again || l->omittedMayReach(info.m_timeStep);
    l->setNearRowsOnly(false);
  }
  if (!again) return;
  // A joint without a row was sent towards its bound: solve again with every row.
  mb.setBaseOmega(btVector3(velocities_[0], velocities_[1], velocities_[2]));
  mb.setBaseVel(btVector3(velocities_[3], velocities_[4], velocities_[5]));
  for (int l = 0; l < mb.getNumLinks(); ++l) {
    if (mb.getLink(l).m_dofCount > 0) {
      mb.setJointVelMultiDof(l, &velocities_[6 + mb.getLink(l).m_dofOffset]);
    }
  }
  mb.clearConstraintForces();
  solveConstraintsAfterServos(info);
}

void ServoWorld::solveConstraintsAfterServos(btContactSolverInfo& info) {
  // What solveExternalForces() and internalSingleStepSimulation() did before the servos:
  // positions have not moved since, so the frames and islands are the same.
  forwardKinematics();
  calculateSimulationIslands();
  m_sortedMultiBodyConstraints.resize(m_multiBodyConstraints.size());
  for (int i = 0; i < m_multiBodyConstraints.size(); ++i) {
    m_sortedMultiBodyConstraints[i] = m_multiBodyConstraints[i];
  }
  m_sortedMultiBodyConstraints.quickSort(btSortMultiBodyConstraintOnIslandPredicate());
  btMultiBodyConstraint** sorted =
      m_sortedMultiBodyConstraints.size() ? &m_sortedMultiBodyConstraints[0] : nullptr;
  m_sortedConstraints.resize(0);
  m_solverMultiBodyIslandCallback->setup(&info, nullptr, 0, sorted,
                                         m_sortedMultiBodyConstraints.size(), getDebugDrawer());
  m_constraintSolver->prepareSolve(getNumCollisionObjects(), getDispatcher()->getNumManifolds());
  buildIslands();
  solveInternalConstraints(info);
}

bool SerialDantzigSolver::solveMLCP(const btMatrixXu& A, const btVectorXu& b, btVectorXu& x,
                                    const btVectorXu& lo, const btVectorXu& hi,
                                    const btAlignedObjectArray<int>& limit_dependency,
                                    int iterations, bool use_sparsity) {
  // A spin lock: the solves are short (microseconds), sleeping on a mutex costs more.
  static std::atomic_flag busy = ATOMIC_FLAG_INIT;
  while (busy.test_and_set(std::memory_order_acquire)) {
  }
  const bool ok =
      btDantzigSolver::solveMLCP(A, b, x, lo, hi, limit_dependency, iterations, use_sparsity);
  busy.clear(std::memory_order_release);
  return ok;
}

Scene::Scene(const WorldParams& params) {
  btDefaultCollisionConstructionInfo info;
  info.m_defaultMaxPersistentManifoldPoolSize = 64;  // small pools: many scenes
  info.m_defaultMaxCollisionAlgorithmPoolSize = 64;
  config_ = std::make_unique<btDefaultCollisionConfiguration>(info);
  dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
  broadphase_ = std::make_unique<btDbvtBroadphase>();
  // A direct (Dantzig) LCP solve of all joint limits and contacts at once: sequential
  // impulses would serve the left wing's limit before the right's and break the
  // left/right symmetry of a flapping unit.
  lcp_ = std::make_unique<SerialDantzigSolver>();
  solver_ = std::make_unique<btMultiBodyMLCPConstraintSolver>(lcp_.get());
  world_ = std::make_unique<ServoWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                        config_.get());
  world_->setGravity(toBt(params.gravity));
  world_->getSolverInfo().m_numIterations = params.solver_iterations;
  world_->getDispatchInfo().m_deterministicOverlappingPairs = true;
  world_->setLeanSteps(params.lean_steps);
  if (params.ground) addGround(params);
}

Scene::~Scene() {
  if (ground_) world_->removeCollisionObject(ground_.get());
}

void Scene::addGround(const WorldParams& params) {
  // A large flat box rather than an infinite plane: its finite bounding box lets the
  // broadphase skip all contact work while the creature is in the air.
  const btScalar half = 1000.0, depth = 1.0;
  ground_shape_ = std::make_unique<btBoxShape>(btVector3(half, half, depth));
  ground_ = std::make_unique<btCollisionObject>();
  ground_->setCollisionShape(ground_shape_.get());
  ground_->setWorldTransform(btTransform(btQuaternion::getIdentity(), btVector3(0, 0, -depth)));
  ground_->setFriction(params.ground_friction);
  world_->addCollisionObject(ground_.get());
}

}  // namespace flapsim
