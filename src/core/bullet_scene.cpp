#include "bullet_scene.h"

#include <BulletDynamics/Featherstone/btMultiBodyMLCPConstraintSolver.h>

#include <atomic>

namespace flapsim {

void ServoWorld::performDiscreteCollisionDetection() {
  if (may_touch_ && !may_touch_()) return;
  btMultiBodyDynamicsWorld::performDiscreteCollisionDetection();
}

void ServoWorld::solveExternalForces(btContactSolverInfo& info) {
  btMultiBodyDynamicsWorld::solveExternalForces(info);
  if (servos_) servos_();
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
