// The added mass of plates: the fluid a plate carries along when it moves along its normal,
// strip theory reduced by the plate's aspect ratio (DNV-RP-C205 table A-2), spread over the plate's
// cells as point masses that act along the normal. The world treats it implicitly (an inertia added
// in the velocity update: a wing in water carries ~175 times its own mass and stays stable). Pure
// functions. Private to flapsim_core.
#pragma once

#include <vector>

#include "dynamics/spatial.h"
#include "flapsim/air_model.h"
#include "flapsim/types.h"

namespace flapsim {

/// The added-mass coefficient C_A of a rectangular plate of sides c <= b moving along its
/// normal, from DNV-RP-C205 "Environmental conditions and environmental loads" (Det Norske
/// Veritas, 2010), Appendix A, table A-2 (rectangular plates): 0.579 at b / c = 1, 0.642 at
/// 1.25, 0.690 at 1.5, 0.704 at 1.59, 0.757 at 2, 0.801 at 2.5, 0.830 at 3, 0.871 at 4,
/// 0.897 at 5, 0.917 at 6.25, 0.934 at 8, 0.947 at 10 and 1 for an infinite strip; linear in
/// c / b between the table's rows. Strip theory (C_A = 1) holds only for the infinite plate:
/// the flow escapes round a finite plate's ends.
double plateAddedMassCoefficient(double chord, double span);

/// Added mass of a flat plate moving along its normal: C_A rho pi c^2 b / 4, c the shorter
/// edge, b the longer, C_A = plateAddedMassCoefficient(c, b) (strip theory's rho pi c^2 b / 4,
/// Sane & Dickinson 2002, Whitney & Wood 2010, times the finite plate's reduction).
double plateAddedMass(double density, double chord, double span);

/// A box is plate-like when its thinnest edge is at most this fraction of the middle one.
constexpr double kPlateThickness = 0.25;

/// A point mass of the fluid that acts only along `normal` (body/COM frame).
struct NormalMass {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  double mass = 0.0;
};

/// The added mass of a plate-like box (size, pose in the body frame) at density 1: spread
/// over an nu x nv grid of its mid-plane, each cell's share acting along the plate normal
/// at the cell centre (appends nothing for a box that is not plate-like).
void appendPlateAddedMass(std::vector<NormalMass>& masses, const Vec3& size, const Pose& origin,
                          int nu, int nv);

/// What the fluid carried by a body does to it beyond resisting the velocity change the servo
/// stage solves it for: with its added mass A (spatial, about the body's COM, world axes;
/// factored), its motion nu = [omega; v] relative to the fluid (v of the COM) and momentum
/// h = A nu, the wrench -(A bias + nu x* h) about the COM (world frame), nu x* h =
/// [omega x h_angular + v x h_linear; omega x h_linear]: Kirchhoff's velocity products (the Munk
/// moment -v x h_linear among them), and A times `bias`, the part of the body's spatial
/// acceleration at its COM that the solved velocity change leaves out (world/fluid_stage.cpp).
/// With the solve's -A dnu it is the force of the fluid's own equations, under which body and
/// fluid keep their kinetic energy; it is internal to body and fluid (their momentum counts h).
Wrench addedMassVelocityWrench(const SpatialFactor& added, const Vec3& omega, const Vec3& velocity,
                               const Vec6& bias);

/// The velocity products a plate sheds into the wake (AddedMassProducts::kShed): with its added
/// mass A (as addedMassVelocityWrench's) and motion nu = [omega; v] relative to the fluid, the
/// wrench nu x* h about its COM (world frame) that gives the products back to the plate, and the
/// linear part of its momentum h = A nu.
struct ShedProducts {
  Wrench wrench;
  Vec3 linear_momentum = Vec3::Zero();

  /// The part of `wrench` external to body and fluid, about the plate's COM: the whole
  /// creature's share of its moment, (V - U) x h_linear (`centre_relative_velocity` = V - U,
  /// the creature's centre of mass relative to the fluid), is the Munk term the momentum
  /// balance leaves out in this air (MomentumBalance::begin).
  Wrench external(const Vec3& centre_relative_velocity) const;
};

ShedProducts shedProducts(const SpatialFactor& added, const Vec3& omega, const Vec3& velocity);
/// The same from nu and its momentum h = A nu, where the caller has h already.
ShedProducts shedProducts(const Vec6& nu, const Vec6& h);

/// Sum of w f f^T over `masses` (times `scale`, e.g. the density), about the body's COM in
/// body axes: constant for a rigid body.
Mat6 normalInertia(const std::vector<NormalMass>& masses, double scale);

}  // namespace flapsim
