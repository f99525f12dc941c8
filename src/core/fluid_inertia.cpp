#include "flapsim/fluid_inertia.h"

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
  const Eigen::SelfAdjointEigenSolver<Mat6> eigen(0.5 * (m + m.transpose()));
  const Vec6& values = eigen.eigenvalues();  // increasing
  const double floor = 1e-13 * values[5];
  for (int i = 5; i >= 0 && values[i] > floor; --i) {
    f.columns.col(f.rank++) = std::sqrt(values[i]) * eigen.eigenvectors().col(i);
  }
  return f;
}

namespace {

// The first N columns of `f` (those past its rank are zero), turned or moved.
template <int N>
void turnColumns(const SpatialFactor& body, const Mat3& rotation, SpatialFactor& out) {
  out.columns.topLeftCorner<3, N>().noalias() = rotation * body.columns.topLeftCorner<3, N>();
  out.columns.bottomLeftCorner<3, N>().noalias() = rotation * body.columns.bottomLeftCorner<3, N>();
}

template <int N>
void addColumnsMatrix(const SpatialFactor& f, const Vec3& offset, Mat6& out) {
  // A force [a; n] about the COM is [a + offset x n; n] about the point.
  Eigen::Matrix<double, 6, N> g = f.columns.leftCols<N>();
  g.template topRows<3>().noalias() += skew(offset) * f.columns.bottomLeftCorner<3, N>();
  out.noalias() += g * g.transpose();
}

}  // namespace

void turnFactor(const SpatialFactor& body, const Mat3& rotation, double scale, SpatialFactor& out) {
  out.rank = body.rank;
  if (body.rank == 0) return;
  const Mat3 r = std::sqrt(scale) * rotation;
  if (body.rank <= 3) {
    turnColumns<3>(body, r, out);
  } else {
    turnColumns<6>(body, r, out);
  }
}

void addFactorMatrix(const SpatialFactor& f, const Vec3& offset, Mat6& out) {
  if (f.rank == 0) return;
  if (f.rank <= 3) {
    addColumnsMatrix<3>(f, offset, out);
  } else {
    addColumnsMatrix<6>(f, offset, out);
  }
}

Vec6 factorTimes(const SpatialFactor& f, const Vec6& v) {
  if (f.rank == 0) return Vec6::Zero();
  if (f.rank <= 3) {
    const auto g = f.columns.leftCols<3>();
    return g * (g.transpose() * v);
  }
  return f.columns * (f.columns.transpose() * v);
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
