#include "dynamics/spatial.h"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace flapsim {

Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0.0, -v.z(), v.y(), v.z(), 0.0, -v.x(), -v.y(), v.x(), 0.0;
  return m;
}

Mat6 spatialInertia(double mass, const Vec3& com, const Mat3& inertia) {
  // -m [c]x [c]x = m (|c|^2 1 - c c^T), without the 3x3 product.
  const Vec3 mc = mass * com;
  const Mat3 c = skew(mc);
  Mat6 out;
  out.topLeftCorner<3, 3>() = inertia - mc * com.transpose();
  out.topLeftCorner<3, 3>().diagonal().array() += mc.dot(com);
  out.topRightCorner<3, 3>() = c;
  out.bottomLeftCorner<3, 3>() = -c;
  out.bottomRightCorner<3, 3>() = mass * Mat3::Identity();
  return out;
}

Vec6 solveSymmetric(const Mat6& a, const Vec6& b) {
  // a = L D L^T (L unit lower triangular), column by column, without square roots: the
  // dependent chain from one column to the next is a division and a product instead of a
  // square root, a division and a product. The diagonal is kept as its inverse, and
  // w[j][k] = l[j][k] d[k] once per row.
  double l[6][6];
  double w[6][6];
  double d[6];
  double inv[6];
#pragma GCC unroll 6
  for (int j = 0; j < 6; ++j) {
    double dj = a(j, j);
#pragma GCC unroll 6
    for (int k = 0; k < j; ++k) {
      w[j][k] = l[j][k] * d[k];
      dj -= l[j][k] * w[j][k];
    }
    d[j] = dj;
    inv[j] = 1.0 / dj;
#pragma GCC unroll 6
    for (int i = j + 1; i < 6; ++i) {
      double s = a(i, j);
#pragma GCC unroll 6
      for (int k = 0; k < j; ++k) s -= l[i][k] * w[j][k];
      l[i][j] = s * inv[j];
    }
  }
  double x[6];
#pragma GCC unroll 6
  for (int i = 0; i < 6; ++i) {  // L y = b
    double s = b[i];
#pragma GCC unroll 6
    for (int k = 0; k < i; ++k) s -= l[i][k] * x[k];
    x[i] = s;
  }
#pragma GCC unroll 6
  for (int i = 5; i >= 0; --i) {  // D L^T x = y
    double s = x[i] * inv[i];
#pragma GCC unroll 6
    for (int k = i + 1; k < 6; ++k) s -= l[k][i] * x[k];
    x[i] = s;
  }
  Vec6 out;
  out << x[0], x[1], x[2], x[3], x[4], x[5];
  return out;
}

void addNormalWeight(Mat6& out, const Vec3& a, const Vec3& n, double w) {
  out.topLeftCorner<3, 3>().noalias() += w * a * a.transpose();
  out.topRightCorner<3, 3>().noalias() += w * a * n.transpose();
  out.bottomLeftCorner<3, 3>().noalias() += w * n * a.transpose();
  out.bottomRightCorner<3, 3>().noalias() += w * n * n.transpose();
}

Mat6 spatialToCommonFrame(const Mat6& body, const Quat& orientation, const Vec3& offset) {
  // Rotation to world axes, then the shift of the reference point: a force f at the COM
  // has the moment offset x f about the point, so the force transform is T = [1 S; 0 1]
  // (S = offset^). Block by block (3x3): X body X^T with X = T diag(r, r), without the
  // products by X's zero and identity blocks.
  Mat6 out = body;
  if (orientation.coeffs() != Quat::Identity().coeffs()) {
    const Mat3 r = orientation.toRotationMatrix();
    for (int i = 0; i < 6; i += 3) {
      for (int j = 0; j < 6; j += 3) {
        out.block<3, 3>(i, j) = r * body.block<3, 3>(i, j) * r.transpose();
      }
    }
  }
  if (offset.isZero(0.0)) return out;
  const Mat3 s = skew(offset);
  const Mat3 top_right = out.topRightCorner<3, 3>() + s * out.bottomRightCorner<3, 3>();
  out.topLeftCorner<3, 3>() += s * out.bottomLeftCorner<3, 3>() + top_right * s.transpose();
  out.bottomLeftCorner<3, 3>() += out.bottomRightCorner<3, 3>() * s.transpose();
  out.topRightCorner<3, 3>() = top_right;
  return out;
}

SpatialFactor factorSpatial(const Mat6& m) {
  SpatialFactor f;
  if (m.isZero(0.0)) return f;
  f.any = true;
  const Mat6 a = 0.5 * (m + m.transpose());
  // a = [P Q; Q^T S]: with S = V L V^T, the columns [Q v / sqrt(l); sqrt(l) v] carry S and Q
  // (Q^T lies in the range of S, a being semi-definite), and P less their moments is the
  // Schur complement, a moment-only part.
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(a.bottomRightCorner<3, 3>());
  const Vec3& values = eigen.eigenvalues();  // increasing
  const double floor = 1e-13 * values[2];
  f.angular = a.topLeftCorner<3, 3>();
  for (int i = 2; i >= 0 && values[i] > floor; --i) {
    const double root = std::sqrt(values[i]);
    const Vec3 v = eigen.eigenvectors().col(i);
    Vec6 g;
    g << a.topRightCorner<3, 3>() * v / root, root * v;
    f.columns.col(f.rank++) = g;
    f.angular.noalias() -= g.head<3>() * g.head<3>().transpose();
  }
  f.angular = 0.5 * (f.angular + f.angular.transpose()).eval();
  return f;
}

void turnFactor(const SpatialFactor& body, const Mat3& rotation, double scale, SpatialFactor& out) {
  out.any = body.any;
  out.rank = body.rank;
  if (!body.any) return;
  out.angular.noalias() = (scale * rotation) * body.angular * rotation.transpose();
  const Mat3 r = std::sqrt(scale) * rotation;
  if (body.rank == 1) {  // a plate
    out.columns.col(0) << r * body.columns.col(0).head<3>(), r * body.columns.col(0).tail<3>();
  } else {
    out.columns.topRows<3>().noalias() = r * body.columns.topRows<3>();
    out.columns.bottomRows<3>().noalias() = r * body.columns.bottomRows<3>();
  }
}

void addFactorMatrix(const SpatialFactor& f, const Vec3& offset, Mat6& out) {
  if (!f.any) return;
  out.topLeftCorner<3, 3>() += f.angular;  // a pure moment: the same about every point
  for (int j = 0; j < f.rank; ++j) {
    // A force [a; n] about the COM is [a + offset x n; n] about the point.
    Vec6 g = f.columns.col(j);
    g.head<3>() += offset.cross(g.tail<3>());
    out.noalias() += g * g.transpose();
  }
}

Vec6 factorTimes(const SpatialFactor& f, const Vec6& v) {
  Vec6 out = Vec6::Zero();
  if (!f.any) return out;
  out.head<3>().noalias() = f.angular * v.head<3>();
  for (int j = 0; j < f.rank; ++j) out += f.columns.col(j) * f.columns.col(j).dot(v);
  return out;
}

}  // namespace flapsim
