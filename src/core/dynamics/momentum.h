// Momentum of a free tree of rigid bodies, and the correction that keeps it true.
//
// A semi-implicit step in joint coordinates (velocities first, then positions from the new
// velocities) conserves neither the linear nor the angular momentum of a free tree whose
// joints move: the Coriolis terms are taken at the start of the step and the positions of
// the links move along straight lines in joint space, not along the arcs the momentum
// balance needs. The error is first order in the step over a fixed time (a flap unit at
// 40 rad/s drifts by 1.4 m in 3 s at 1 ms). The world therefore carries the momentum as a
// quantity of its own: it adds the external impulses of each step (gravity, air, the
// fluid's implicit part) to the momentum at the start, moves the centre of mass with the
// new linear momentum, and after Bullet's step gives the base the rigid twist and
// translation that make the tree match. Internal forces then cannot move the centre of
// mass nor change the angular momentum, at any step size. Pure functions: no Bullet.
#pragma once

#include <vector>

#include "dynamics/spatial.h"
#include "flapsim/types.h"

namespace flapsim {

struct SpatialFactor;  // flapsim/fluid_inertia.h

/// One rigid body at an instant, world frame.
struct BodyMotion {
  double mass = 0.0;
  Vec3 com = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();   // about the body's COM, world axes
  Vec3 velocity = Vec3::Zero();  // of the COM
  Vec3 angular_velocity = Vec3::Zero();
};

/// The momentum of a set of bodies about their common centre of mass, and optionally that
/// of the fluid they carry along (their added mass): with it, `linear` and `angular` are
/// Kirchhoff's impulse of body and fluid, which internal forces do not change either.
struct SystemMomentum {
  double mass = 0.0;
  Vec3 com = Vec3::Zero();
  Vec3 linear = Vec3::Zero();       // bodies and fluid
  Vec3 angular = Vec3::Zero();      // bodies and fluid, about `com`
  Vec3 body_linear = Vec3::Zero();  // the bodies' own: mass x velocity of `com`
  Mat3 inertia = Mat3::Zero();      // the bodies' composite, about `com` (the tree as if rigid)
  Mat6 fluid = Mat6::Zero();        // the added mass, spatial, about `com`, world axes
};

SystemMomentum systemMomentum(const std::vector<BodyMotion>& bodies);

/// Adds the fluid carried by one body: its added mass `added` (spatial, about the body's
/// COM `com`, world axes; factored, flapsim/fluid_inertia.h) moving with the body's
/// `velocity` [angular; linear of the COM]; returns that fluid's momentum h = A velocity
/// [moment about `com`; linear].
Vec6 addFluidMomentum(SystemMomentum& s, const SpatialFactor& added, const Vec3& com,
                      const Vec6& velocity);

/// The rigid motion that brings a tree from `actual` to the target momentum: add
/// `angular_velocity` and `velocity` + angular_velocity x (x - com) to the velocity of every
/// point x (the fluid's share of the momentum moves along).
struct RigidCorrection {
  Vec3 velocity = Vec3::Zero();  // at the centre of mass
  Vec3 angular_velocity = Vec3::Zero();
};

RigidCorrection momentumCorrection(const SystemMomentum& actual, const Vec3& linear,
                                   const Vec3& angular);

}  // namespace flapsim
