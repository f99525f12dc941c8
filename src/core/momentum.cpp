#include "flapsim/momentum.h"

#include <Eigen/Cholesky>

namespace flapsim {

SystemMomentum systemMomentum(const std::vector<BodyMotion>& bodies) {
  SystemMomentum s;
  Vec3 weighted = Vec3::Zero();
  for (const BodyMotion& b : bodies) {
    s.mass += b.mass;
    weighted += b.mass * b.com;
    s.linear += b.mass * b.velocity;
  }
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

RigidCorrection momentumCorrection(const SystemMomentum& actual, const Vec3& linear,
                                   const Vec3& angular, const Vec3& com) {
  RigidCorrection c;
  if (actual.mass <= 0.0) return c;
  c.velocity = (linear - actual.linear) / actual.mass;
  // A rigid spin about the centre of mass adds inertia x spin to the angular momentum
  // about it and nothing to the linear momentum.
  c.angular_velocity = actual.inertia.ldlt().solve(angular - actual.angular);
  c.shift = com - actual.com;
  return c;
}

}  // namespace flapsim
