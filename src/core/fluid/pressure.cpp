#include "fluid/pressure.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "flapsim/world.h"
#include "fluid/body_flow.h"

namespace flapsim {

namespace {

// u.n and |u|^2 over a grid face's cells (a, b) as polynomials in the cell indices (see
// PressureAirModel::bodyWrench): u.n = n0 + a n_a + b n_b, |u|^2 = q00 + a q0a + b q0b +
// a^2 qaa + a b qab + b^2 qbb.
struct GridAxes {
  double n0, n_a, n_b;
  double q00, q0a, q0b, qaa, qab, qbb;
};

// Sums over the cells of |u| max(u.n, 0) (the pressure without its constant factor), and
// of it times a and times b.
struct GridSums {
  double sum = 0.0, across = 0.0, along = 0.0;
};

// Two cells of a row at a time, in the two lanes of a SIMD register (square roots too); a
// lane past the row's end is weighted zero. kRows and kCols, when not 0, are rows and cols
// known at compile time (the usual grids: the loops unroll).
template <int kRows, int kCols>
GridSums gridSums(const GridAxes& g, int rows_in, int cols_in) {
  using Pair = Eigen::Array2d;
  const int rows = kRows > 0 ? kRows : rows_in, cols = kCols > 0 ? kCols : cols_in;
  const Pair step(0.0, 1.0), last(1.0, cols % 2 == 0 ? 1.0 : 0.0);
  Pair sum = Pair::Zero(), across = Pair::Zero(), along = Pair::Zero();
  for (int a = 0; a < rows; ++a) {
    const double un_a = g.n0 + a * g.n_a;
    const double q_a = g.q00 + a * (g.q0a + a * g.qaa), q_ab = g.q0b + a * g.qab;
    Pair row = Pair::Zero(), row_b = Pair::Zero();
    for (int b0 = 0; b0 < cols; b0 += 2) {
      const Pair b = step + static_cast<double>(b0);
      const Pair un = (un_a + b * g.n_b).max(0.0);
      Pair p = (q_a + b * (q_ab + b * g.qbb)).max(0.0).sqrt() * un;
      if (b0 + 2 > cols) p *= last;
      row += p;
      row_b += p * b;
    }
    sum += row;
    across += static_cast<double>(a) * row;
    along += row_b;
  }
  return GridSums{sum.sum(), across.sum(), along.sum()};
}

// A 4 x 4 grid (a box's face): two rows at a time instead, in the lanes (a, a + 1), which
// broadcasts per column what gridSums broadcasts per row. The same cells, summed in another
// order.
GridSums gridSums4x4(const GridAxes& g) {
  using Pair = Eigen::Array2d;
  Pair sum = Pair::Zero(), across = Pair::Zero(), along = Pair::Zero();
  for (int a0 = 0; a0 < 4; a0 += 2) {
    const Pair a = Pair(0.0, 1.0) + static_cast<double>(a0);
    const Pair un_a = g.n0 + a * g.n_a;
    const Pair q_a = g.q00 + a * (g.q0a + a * g.qaa), q_ab = g.q0b + a * g.qab;
    Pair row = Pair::Zero(), row_b = Pair::Zero();
    for (int j = 0; j < 4; ++j) {
      const double b = j;
      const Pair un = (un_a + b * g.n_b).max(0.0);
      const Pair p = (q_a + b * (q_ab + b * g.qbb)).max(0.0).sqrt() * un;
      row += p;
      row_b += p * b;
    }
    sum += row;
    across += a * row;
    along += row_b;
  }
  return GridSums{sum.sum(), across.sum(), along.sum()};
}

GridSums gridSums(const GridAxes& g, int rows, int cols) {
  if (cols == 4) {
    if (rows == 4) return gridSums4x4(g);
    if (rows == 1) return gridSums<1, 4>(g, rows, cols);
    return gridSums<0, 4>(g, rows, cols);
  }
  return gridSums<0, 0>(g, rows, cols);
}

// The forces on row i of grid face `face` (see PressureAirModel::bodyWrench), world frame.
void recordRow(const SurfaceFace& face, int i, double un_i, double n_j, double k, double q_i,
               double q_ij, double qjj, const Eigen::Matrix3d& rot, std::vector<Vec3>& out) {
  for (int j = 0; j < face.nv; ++j) {
    const double un = un_i + j * n_j;
    if (un <= 0.0) continue;
    const double p = k * std::sqrt(std::max(0.0, q_i + j * (q_ij + j * qjj))) * un;
    out[face.first_cell + i * face.nv + j] = rot * (-p * face.normal);
  }
}

// The pressure on a face whose cells are a plain list (some hidden), cell by cell, added to
// `force` and `torque` (body frame).
void addListFace(const BodyFlow& flow, const AeroSurface& surface, const SurfaceFace& face,
                 double density, double cd, std::vector<Vec3>* cell_forces, Vec3& force,
                 Vec3& torque) {
  double sum = 0.0;
  Vec3 moment = Vec3::Zero();
  for (int i = face.first_cell; i < face.first_cell + face.cell_count; ++i) {
    const SurfaceCell& cell = surface.cells[i];
    const double p = pressureMagnitude(flow.at(cell.centre), face.normal, cell.area, density, cd);
    sum += p;
    moment += p * cell.centre;
    if (cell_forces) (*cell_forces)[i] = flow.rot * (-p * face.normal);
  }
  force -= sum * face.normal;
  torque -= moment.cross(face.normal);
}

}  // namespace

// Flattened: its small helpers and Eigen products inline into the loops, whatever the
// inliner's budget (instructions, not results, depend on it).
__attribute__((flatten)) Wrench pressureLaw(const FluidInput& in, std::vector<Vec3>* cell_forces) {
  const BodyKinematics& body = in.body;
  const AeroSurface& surface = in.surface;
  const AirParams& air = in.air;
  const double cd = surface.drag_coefficient;
  if (surface.faces.empty()) {
    return sumCells(body, surface, air, cell_forces,
                    [&](const Vec3& u, const SurfaceCell& cell, const Vec3&) {
                      return pressureForce(u, cell.normal, cell.area, air.density, cd);
                    });
  }
  // Per face: every force is along the face's normal n, so the face's force is -(sum p_i) n
  // and its torque -(sum p_i c_i) x n; only magnitudes are summed per cell.
  const BodyFlow flow(body, air);
  const Vec3 drift = flow.v - flow.wind;  // the air's velocity relative to the COM
  const double half_rho_cd = 0.5 * air.density * cd;
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
  if (cell_forces) cell_forces->assign(surface.cells.size(), Vec3::Zero());
  // The cell steps' velocity terms of the last grid computed, shared by faces with the same
  // steps (a box's opposite faces).
  int steps_of = -1;
  Vec3 du = Vec3::Zero(), dv = Vec3::Zero();
  double qii = 0.0, qij = 0.0, qjj = 0.0;
  for (const SurfaceFace& face : surface.faces) {
    if (face.nu > 0) {
      // On a grid the relative velocity is affine in the cell index (u(c + s) = u(c) + w x s),
      // and so is the centre: sum p, p i and p j, not vectors. Then u.n is affine in (i, j)
      // and |u|^2 a quadratic: a cell costs a few multiply-adds and one square root.
      const Vec3& n = face.normal;
      // u.n = v.n + (w x r).n = v.n + w.(r x n): no cross product before the test below.
      const double n0 = drift.dot(n) + flow.w.dot(face.centre_x_normal);
      const double n_i = flow.w.dot(face.step_u_x_normal), n_j = flow.w.dot(face.step_v_x_normal);
      // The largest u.n over the cell centres: if none advances into the air, none is pushed.
      if (n0 + std::max(0.0, (face.nu - 1) * n_i) + std::max(0.0, (face.nv - 1) * n_j) <= 0.0) {
        continue;
      }
      const SurfaceCell& first = surface.cells[face.first_cell];
      const Vec3 u0 = flow.at(first.centre);
      if (face.steps_of != steps_of) {
        du = flow.w.cross(face.step_u);
        dv = flow.w.cross(face.step_v);
        qii = du.squaredNorm();
        qij = 2.0 * du.dot(dv);
        qjj = dv.squaredNorm();
        steps_of = face.steps_of;
      }
      const double k = half_rho_cd * first.area;
      const double q00 = u0.squaredNorm(), q0i = 2.0 * u0.dot(du), q0j = 2.0 * u0.dot(dv);
      // Vectors run along the longer edge of the grid (a plate's rim is one cell wide).
      GridSums g;
      if (face.nv >= face.nu) {
        g = gridSums(GridAxes{n0, n_i, n_j, q00, q0i, q0j, qii, qij, qjj}, face.nu, face.nv);
      } else {
        g = gridSums(GridAxes{n0, n_j, n_i, q00, q0j, q0i, qjj, qij, qii}, face.nv, face.nu);
        std::swap(g.across, g.along);
      }
      if (cell_forces) {
        for (int i = 0; i < face.nu; ++i) {
          recordRow(face, i, n0 + i * n_i, n_j, k, q00 + i * (q0i + i * qii), q0j + i * qij, qjj,
                    flow.rot, *cell_forces);
        }
      }
      // The torque -(sum c_i p_i) x n from the centres' cross products with n.
      const double p = k * g.sum;
      force -= p * n;
      torque -= p * face.centre_x_normal + (k * g.across) * face.step_u_x_normal +
                (k * g.along) * face.step_v_x_normal;
      continue;
    }
    if (flow.advances(face))
      addListFace(flow, surface, face, air.density, cd, cell_forces, force, torque);
  }
  return Wrench{flow.rot * force, flow.rot * torque};
}

Mat6 pressureDragDamping(const FluidInput& in) {
  const BodyKinematics& body = in.body;
  const AeroSurface& surface = in.surface;
  const AirParams& air = in.air;
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

std::string PressureAirModel::check(const AirParams& air) const {
  const double cd = air.drag_coefficient;
  if (std::isfinite(cd) && cd >= 0.0 && cd <= kMaxDragCoefficient) return "";
  return "air drag_coefficient must be in [0, 1000]";
}

}  // namespace flapsim
