#include "dynamics/momentum.h"

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include "dynamics/spatial.h"

namespace flapsim {

SystemMomentum systemMomentum(const std::vector<BodyMotion>& bodies) {
  SystemMomentum s;
  Vec3 weighted = Vec3::Zero();
  for (const BodyMotion& b : bodies) {
    s.mass += b.mass;
    weighted += b.mass * b.com;
    s.linear += b.mass * b.velocity;
  }
  s.body_linear = s.linear;
  if (s.mass <= 0.0) return s;
  s.com = weighted / s.mass;
  for (const BodyMotion& b : bodies) {
    const Vec3 r = b.com - s.com;
    s.angular += b.inertia * b.angular_velocity + b.mass * r.cross(b.velocity);
    // I + m (|r|^2 1 - r r^T): the body's inertia moved to the common centre.
    s.inertia += b.inertia;
    s.inertia += b.mass * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  return s;
}

Vec6 addFluidMomentum(SystemMomentum& s, const SpatialFactor& added, const Vec3& com,
                      const Vec6& velocity) {
  const Vec6 h = factorTimes(added, velocity);  // [moment about the body's COM; force]
  const Vec3 r = com - s.com;
  s.linear += h.tail<3>();
  s.angular += h.head<3>() + r.cross(h.tail<3>());
  addFactorMatrix(added, r, s.fluid);  // about the common centre
  return h;
}

RigidCorrection momentumCorrection(const SystemMomentum& actual, const Vec3& linear,
                                   const Vec3& angular) {
  RigidCorrection c;
  if (actual.mass <= 0.0) return c;
  // A rigid twist [w; v] about the centre of mass adds [I w; M v] to the bodies' momentum
  // and fluid x [w; v] to the fluid's.
  if (actual.fluid.isZero(0.0)) {  // no fluid: the angular and linear parts apart
    c.angular_velocity = actual.inertia.llt().solve(angular - actual.angular);
    c.velocity = (linear - actual.linear) / actual.mass;
    return c;
  }
  Mat6 k = actual.fluid;
  k.topLeftCorner<3, 3>() += actual.inertia;
  k.bottomRightCorner<3, 3>() += actual.mass * Mat3::Identity();
  Vec6 change;
  change << angular - actual.angular, linear - actual.linear;
  const Vec6 twist = solveSymmetric(k, change);
  c.angular_velocity = twist.head<3>();
  c.velocity = twist.tail<3>();
  return c;
}

}  // namespace flapsim
