// Spatial algebra of the core: 6-vectors [angular; linear at a point] and 6x6 matrices
// about a point, the cross-product matrix, spatial inertias, symmetric solves, and the
// factored form of a spatial inertia-like matrix that the fluid's added mass travels in.
// Pure functions: no Bullet, no state.
//
// Spatial vectors are [angular; linear at a point]; a unit force n at a point offset r
// from that point is the spatial force f = [r x n; n], and the normal velocity of that
// point under a spatial velocity V is f^T V. A weight w acting along n at r therefore
// contributes w f f^T.
#pragma once

#include <Eigen/Core>

#include "flapsim/types.h"

namespace flapsim {

using Mat3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// The cross-product matrix: skew(v) * x = v x x.
Mat3 skew(const Vec3& v);
/// Spatial inertia about the frame origin, for velocities [angular; linear at origin].
Mat6 spatialInertia(double mass, const Vec3& com, const Mat3& inertia);
/// Solves a x = b for a symmetric positive definite `a` (its lower triangle is read) by
/// a square-root-free Cholesky (L D L^T, no pivoting): a.ldlt().solve(b) up to rounding,
/// unrolled for the 6x6 case.
Vec6 solveSymmetric(const Mat6& a, const Vec6& b);

/// Adds w f f^T for the spatial force f = [a; n] (a = r x n) to `out`.
void addNormalWeight(Mat6& out, const Vec3& a, const Vec3& n, double w);

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

/// Spatial cross products at one point ([angular; linear]): of a motion `v` with a motion `m`,
/// [w_v x w_m; w_v x v_m + v_v x w_m], and with a force `f`, [w x n_f + v x f_f; w x f_f].
inline Vec6 crossMotion(const Vec6& v, const Vec6& m) {
  Vec6 out;
  out << v.head<3>().cross(m.head<3>()),
      v.head<3>().cross(m.tail<3>()) + v.tail<3>().cross(m.head<3>());
  return out;
}
inline Vec6 crossForce(const Vec6& v, const Vec6& f) {
  Vec6 out;
  out << v.head<3>().cross(f.head<3>()) + v.tail<3>().cross(f.tail<3>()),
      v.head<3>().cross(f.tail<3>());
  return out;
}

/// The moment about `point` of a spatial impulse [moment about `origin`; force].
inline Vec3 momentAbout(const Vec6& impulse, const Vec3& origin, const Vec3& point) {
  return impulse.head<3>() + (origin - point).cross(impulse.tail<3>());
}

}  // namespace flapsim
