#include "fluid/fluid_inertia.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace flapsim {

namespace {

// w f f^T for f = [a; n], a = r x n, added to `out`.
void addNormalWeight(Mat6& out, const Vec3& a, const Vec3& n, double w) {
  out.topLeftCorner<3, 3>().noalias() += w * a * a.transpose();
  out.topRightCorner<3, 3>().noalias() += w * a * n.transpose();
  out.bottomLeftCorner<3, 3>().noalias() += w * n * a.transpose();
  out.bottomRightCorner<3, 3>().noalias() += w * n * n.transpose();
}

}  // namespace

double plateAddedMass(double density, double chord, double span) {
  return density * M_PI * chord * chord * span / 4.0;
}

void appendPlateAddedMass(std::vector<NormalMass>& masses, const Vec3& size, const Pose& origin,
                          int nu, int nv) {
  int thin = 0;
  size.minCoeff(&thin);
  const int b = (thin + 1) % 3, c = (thin + 2) % 3;
  const double chord = std::min(size[b], size[c]), span = std::max(size[b], size[c]);
  if (size[thin] > kPlateThickness * chord || chord <= 0.0) return;
  const double total = plateAddedMass(1.0, chord, span);
  Vec3 normal = Vec3::Zero();
  normal[thin] = 1.0;
  normal = origin.orientation * normal;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      Vec3 p = Vec3::Zero();
      p[b] = ((i + 0.5) / nu - 0.5) * size[b];
      p[c] = ((j + 0.5) / nv - 0.5) * size[c];
      masses.push_back(NormalMass{origin.apply(p), normal, total / (nu * nv)});
    }
  }
}

Mat6 normalInertia(const std::vector<NormalMass>& masses, double scale) {
  Mat6 out = Mat6::Zero();
  for (const NormalMass& m : masses) {
    addNormalWeight(out, m.point.cross(m.normal), m.normal, scale * m.mass);
  }
  return out;
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

Mat6 dragDamping(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air) {
  Mat6 out = Mat6::Zero();
  const double k = 0.5 * air.density * surface.drag_coefficient;
  if (k <= 0.0) return out;
  // In the body frame, where cell centres and normals are constant.
  const Quat to_body = body.orientation.conjugate();
  const Vec3 v = to_body * (body.linear_velocity - air.wind);
  const Vec3 w = to_body * body.angular_velocity;
  // The weight of one advancing cell: d|F|/d(u.n) = k s (|u| + (u.n)^2 / |u|).
  auto weight = [k](const Vec3& u, double un, double area) {
    const double speed = u.norm();
    return k * area * (speed + un * un / speed);
  };
  Mat3 saa = Mat3::Zero();  // sums over a face of w a a^T, w a and w, a = c x n
  Vec3 sa = Vec3::Zero();
  double sw = 0.0;
  auto flush = [&out, &saa, &sa, &sw](const Vec3& n) {
    out.topLeftCorner<3, 3>() += saa;
    out.topRightCorner<3, 3>().noalias() += sa * n.transpose();
    out.bottomLeftCorner<3, 3>().noalias() += n * sa.transpose();
    out.bottomRightCorner<3, 3>().noalias() += sw * n * n.transpose();
    saa.setZero();
    sa.setZero();
    sw = 0.0;
  };
  auto cellByCell = [&](int first, int count) {
    for (int c = first; c < first + count; ++c) {
      const SurfaceCell& cell = surface.cells[c];
      const Vec3 u = v + w.cross(cell.centre);
      const double un = u.dot(cell.normal);
      if (un <= 0.0) continue;
      addNormalWeight(out, cell.centre.cross(cell.normal), cell.normal, weight(u, un, cell.area));
    }
  };
  if (surface.faces.empty()) cellByCell(0, static_cast<int>(surface.cells.size()));
  for (const SurfaceFace& face : surface.faces) {
    if (face.nu <= 0 || face.nv <= 0 || face.cell_count != face.nu * face.nv) {
      cellByCell(face.first_cell, face.cell_count);
      continue;
    }
    const Vec3& n = face.normal;
    const SurfaceCell& first = surface.cells[face.first_cell];
    // u, u.n and a are affine in the cell index.
    const Vec3 u0 = v + w.cross(first.centre), du = w.cross(face.step_u), dv = w.cross(face.step_v);
    const double un0 = u0.dot(n), dnu = du.dot(n), dnv = dv.dot(n);
    const double top =
        un0 + std::max(0.0, dnu) * (face.nu - 1) + std::max(0.0, dnv) * (face.nv - 1);
    if (top <= 0.0) continue;  // the whole face retreats
    const Vec3 a0 = first.centre.cross(n), dau = face.step_u.cross(n), dav = face.step_v.cross(n);
    for (int i = 0; i < face.nu; ++i) {
      for (int j = 0; j < face.nv; ++j) {
        const double un = un0 + i * dnu + j * dnv;
        if (un <= 0.0) continue;
        const double wt = weight(u0 + i * du + j * dv, un, first.area);
        const Vec3 a = a0 + i * dau + j * dav;
        saa.noalias() += wt * a * a.transpose();
        sa += wt * a;
        sw += wt;
      }
    }
    flush(n);
  }
  return spatialToCommonFrame(out, body.orientation, Vec3::Zero());
}

}  // namespace flapsim
