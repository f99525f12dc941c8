// The fluid's implicit part: the added mass of plates and the linearised normal drag of
// every advancing cell, each as a symmetric 6x6 spatial matrix that the world adds to a
// body's inertia in the velocity update (so a wing in water, whose added mass is ~175
// times its own, and a drag that would reverse a cell's normal velocity within one step
// both stay stable). Pure functions: no Bullet, no state.
//
// Spatial vectors are [angular; linear at a point]; a unit force n at a point offset r
// from that point is the spatial force f = [r x n; n], and the normal velocity of that
// point under a spatial velocity V is f^T V. A weight w acting along n at r therefore
// contributes w f f^T.
#pragma once

#include <vector>

#include "flapsim/air_model.h"
#include "dynamics/joint_servo.h"
#include "flapsim/types.h"

namespace flapsim {

/// Added mass of a flat plate moving along its normal, strip theory (Sane & Dickinson
/// 2002; Whitney & Wood 2010): rho pi c^2 b / 4, c the shorter edge, b the longer.
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

/// Sum of w f f^T over `masses` (times `scale`, e.g. the density), about the body's COM in
/// body axes: constant for a rigid body.
Mat6 normalInertia(const std::vector<NormalMass>& masses, double scale);

/// A spatial matrix about a body's COM in body axes, turned to world axes by `orientation`
/// and moved to be about a point at `-offset` from the COM (offset = com - point).
Mat6 spatialToCommonFrame(const Mat6& body, const Quat& orientation, const Vec3& offset);

/// A symmetric positive semi-definite spatial matrix, spatial inertia-like, split as a
/// moment-only part (a 3x3 block, the same about every point) plus the sum of g g^T over up
/// to three columns g = [moment; force], which move between points like spatial forces. A
/// plate's added mass has one such column (all its cells push along one normal) and a
/// moment-only rest: it is turned to world axes and moved to a point at a fraction of the
/// cost of its 6x6 blocks.
struct SpatialFactor {
  bool any = false;  // false: the zero matrix
  Mat3 angular = Mat3::Zero();
  Eigen::Matrix<double, 6, 3> columns = Eigen::Matrix<double, 6, 3>::Zero();
  int rank = 0;  // columns in use
};

/// The factor of a symmetric positive semi-definite `m` (its linear block's eigenvalues below
/// 1e-13 of the largest, rounding, left out: the matrix is the same up to rounding).
SpatialFactor factorSpatial(const Mat6& m);

/// `body` (about a body's COM, body axes) times `scale` >= 0, in world axes by `rotation`.
void turnFactor(const SpatialFactor& body, const Mat3& rotation, double scale, SpatialFactor& out);

/// Adds the matrix of `f` (about a body's COM), moved to be about a point at `-offset` from
/// the COM (offset = com - point, as spatialToCommonFrame), to `out`.
void addFactorMatrix(const SpatialFactor& f, const Vec3& offset, Mat6& out);

/// The matrix of `f` times `v`.
Vec6 factorTimes(const SpatialFactor& f, const Vec6& v);

/// Linearised normal drag of the pressure model, about the body's COM in world axes: for
/// each advancing cell, the derivative of its normal force magnitude by its normal speed,
/// 1/2 rho Cd s (|u| + (u.n)^2 / |u|), as a weight along the cell normal. Times the step,
/// it is the damping the world treats implicitly (a stabiliser: the air forces themselves
/// are evaluated by the air model at the start of the step).
Mat6 dragDamping(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air);

}  // namespace flapsim
