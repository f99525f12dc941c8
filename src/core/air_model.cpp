#include "flapsim/air_model.h"

#include <algorithm>
#include <cmath>

namespace flapsim {

std::vector<SurfaceCell> boxSurfaceCells(const Vec3& size, const Pose& origin, int nu, int nv) {
  std::vector<SurfaceCell> cells;
  if (nu < 1 || nv < 1) return cells;
  cells.reserve(static_cast<size_t>(6 * nu * nv));
  for (int axis = 0; axis < 3; ++axis) {
    const int b = (axis + 1) % 3;
    const int c = (axis + 2) % 3;
    const double cell_area = size[b] * size[c] / (nu * nv);
    for (double sign : {1.0, -1.0}) {
      Vec3 normal = Vec3::Zero();
      normal[axis] = sign;
      for (int i = 0; i < nu; ++i) {
        for (int j = 0; j < nv; ++j) {
          Vec3 p = Vec3::Zero();
          p[axis] = sign * 0.5 * size[axis];
          p[b] = size[b] * ((i + 0.5) / nu - 0.5);
          p[c] = size[c] * ((j + 0.5) / nv - 0.5);
          cells.push_back(SurfaceCell{origin.apply(p), origin.orientation * normal, cell_area});
        }
      }
    }
  }
  return cells;
}

void appendBox(AeroSurface& surface, const Vec3& size, const Pose& origin, int nu, int nv) {
  const std::vector<SurfaceCell> cells = boxSurfaceCells(size, origin, nu, nv);
  const int per_face = static_cast<int>(cells.size()) / 6;
  for (int f = 0; f < 6 && per_face > 0; ++f) {
    const int axis = f / 2;
    const double sign = f % 2 == 0 ? 1.0 : -1.0;  // boxSurfaceCells' order
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    SurfaceFace face;
    face.normal = cells[f * per_face].normal;
    Vec3 edge = Vec3::Zero();
    edge[size[b] >= size[c] ? b : c] = 1.0;
    face.span = origin.orientation * edge;
    for (int k = 0; k < 4; ++k) {
      Vec3 p = Vec3::Zero();
      p[axis] = sign * 0.5 * size[axis];
      p[b] = (k & 1 ? 0.5 : -0.5) * size[b];
      p[c] = (k & 2 ? 0.5 : -0.5) * size[c];
      face.corners[k] = origin.apply(p);
    }
    face.first_cell = static_cast<int>(surface.cells.size()) + f * per_face;
    face.cell_count = per_face;
    face.nu = nu;
    face.nv = nv;
    Vec3 step = Vec3::Zero();
    step[b] = size[b] / nu;
    face.step_u = origin.orientation * step;
    step = Vec3::Zero();
    step[c] = size[c] / nv;
    face.step_v = origin.orientation * step;
    surface.faces.push_back(face);
  }
  surface.cells.insert(surface.cells.end(), cells.begin(), cells.end());
  surface.volume += size.prod();
}

namespace {

// The air's motion seen from a body: velocities in the body frame, where cell centres and
// normals are constant.
struct BodyFlow {
  BodyFlow(const BodyKinematics& body, const AirParams& air)
      : rot(body.orientation.toRotationMatrix()),
        v(rot.transpose() * body.linear_velocity),
        w(rot.transpose() * body.angular_velocity),
        wind(rot.transpose() * air.wind) {}

  Vec3 at(const Vec3& point) const { return relativeAirVelocity(v, w, point, wind); }
  // u.n is affine over a face: if no corner advances into the air, no cell does.
  bool advances(const SurfaceFace& face) const {
    for (const Vec3& corner : face.corners) {
      if (at(corner).dot(face.normal) > 0.0) return true;
    }
    return false;
  }

  Eigen::Matrix3d rot;
  Vec3 v, w, wind;
};

// Sums per-cell forces of `force(u, cell, span)` over a body, skipping retreating faces.
template <typename CellForce>
Wrench sumCells(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air,
                std::vector<Vec3>* cell_forces, CellForce force) {
  const BodyFlow flow(body, air);
  Vec3 total = Vec3::Zero(), torque = Vec3::Zero();
  if (cell_forces) cell_forces->assign(surface.cells.size(), Vec3::Zero());
  auto cellRange = [&](int first, int count, const Vec3& span) {
    for (int i = first; i < first + count; ++i) {
      const SurfaceCell& cell = surface.cells[i];
      const Vec3 f = force(flow.at(cell.centre), cell, span);
      if (f.isZero(0.0)) continue;
      total += f;
      torque += cell.centre.cross(f);
      if (cell_forces) (*cell_forces)[i] = flow.rot * f;
    }
  };
  if (surface.faces.empty()) {
    cellRange(0, static_cast<int>(surface.cells.size()), Vec3::Zero());
  } else {
    for (const SurfaceFace& face : surface.faces) {
      if (flow.advances(face)) cellRange(face.first_cell, face.cell_count, face.span);
    }
  }
  return Wrench{flow.rot * total, flow.rot * torque};
}

constexpr double kDeg = M_PI / 180.0;

}  // namespace

Wrench PressureAirModel::bodyWrench(const BodyKinematics& body, const AeroSurface& surface,
                                    const AirParams& air, std::vector<Vec3>* cell_forces) const {
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
  Vec3 force = Vec3::Zero(), torque = Vec3::Zero();
  if (cell_forces) cell_forces->assign(surface.cells.size(), Vec3::Zero());
  for (const SurfaceFace& face : surface.faces) {
    double sum = 0.0;
    Vec3 moment = Vec3::Zero();
    if (face.nu > 0) {
      // On a grid the relative velocity is affine in the cell index (u(c + s) = u(c) + w x s),
      // and so is the centre: sum p, p i and p j, not vectors. Then u.n is affine in (i, j)
      // and |u|^2 a quadratic: a cell costs a few multiply-adds and one square root.
      const SurfaceCell& first = surface.cells[face.first_cell];
      const Vec3& n = face.normal;
      const Vec3 u0 = flow.at(first.centre);
      const Vec3 du = flow.w.cross(face.step_u), dv = flow.w.cross(face.step_v);
      const double n0 = u0.dot(n), n_i = du.dot(n), n_j = dv.dot(n);
      // The largest u.n over the cell centres: if none advances into the air, none is pushed.
      if (n0 + std::max(0.0, (face.nu - 1) * n_i) + std::max(0.0, (face.nv - 1) * n_j) <= 0.0) {
        continue;
      }
      const double k = 0.5 * air.density * cd * first.area;
      const double q00 = u0.squaredNorm(), q0i = 2.0 * u0.dot(du), q0j = 2.0 * u0.dot(dv);
      const double qii = du.squaredNorm(), qij = 2.0 * du.dot(dv), qjj = dv.squaredNorm();
      double sum_i = 0.0, sum_j = 0.0;
      for (int i = 0; i < face.nu; ++i) {
        const double un_i = n0 + i * n_i;
        const double q_i = q00 + i * (q0i + i * qii), q_ij = q0j + i * qij;
        double row = 0.0, row_j = 0.0;
        for (int j = 0; j < face.nv; ++j) {
          const double un = un_i + j * n_j;
          if (un <= 0.0) continue;
          const double p = k * std::sqrt(std::max(0.0, q_i + j * (q_ij + j * qjj))) * un;
          row += p;
          row_j += p * j;
          if (cell_forces) (*cell_forces)[face.first_cell + i * face.nv + j] = flow.rot * (-p * n);
        }
        sum += row;
        sum_i += row * i;
        sum_j += row_j;
      }
      moment = sum * first.centre + sum_i * face.step_u + sum_j * face.step_v;
    } else {
      if (!flow.advances(face)) continue;
      for (int i = face.first_cell; i < face.first_cell + face.cell_count; ++i) {
        const SurfaceCell& cell = surface.cells[i];
        const double p =
            pressureMagnitude(flow.at(cell.centre), face.normal, cell.area, air.density, cd);
        sum += p;
        moment += p * cell.centre;
        if (cell_forces) (*cell_forces)[i] = flow.rot * (-p * face.normal);
      }
    }
    force -= sum * face.normal;
    torque -= moment.cross(face.normal);
  }
  return Wrench{flow.rot * force, flow.rot * torque};
}

double angleOfAttack(const Vec3& u, const Vec3& n) {
  const double speed = u.norm();
  if (speed == 0.0) return 0.0;
  return std::asin(std::min(1.0, std::abs(u.dot(n)) / speed)) / kDeg;
}

double liftCoefficient(double a, const QuasiSteadyCoefficients& c) {
  return c.lift_mean + c.lift_amplitude * std::sin((c.lift_frequency * a + c.lift_phase) * kDeg);
}

double dragCoefficient(double a, const QuasiSteadyCoefficients& c) {
  return c.drag_mean - c.drag_amplitude * std::cos((c.drag_frequency * a + c.drag_phase) * kDeg);
}

Vec3 quasiSteadyForce(const Vec3& u, const Vec3& n, const Vec3& span, double area, double density,
                      const QuasiSteadyCoefficients& c) {
  // Edge-on within rounding counts as edge-on: C_D(0) > 0 would otherwise give a full
  // face's drag to whichever face rounding happens to tilt forward.
  if (u.dot(n) <= 1e-12 * u.norm()) return Vec3::Zero();
  const Vec3 chordwise = u - u.dot(span) * span;
  const double speed2 = chordwise.squaredNorm();
  if (speed2 == 0.0) return Vec3::Zero();
  const Vec3 drag_dir = -chordwise / std::sqrt(speed2);
  const double alpha = angleOfAttack(chordwise, n);
  const double q = 0.5 * density * area * speed2;
  Vec3 force = q * dragCoefficient(alpha, c) * drag_dir;
  Vec3 lift_dir = -n - (-n).dot(drag_dir) * drag_dir;  // -n without its part along the flow
  lift_dir -= lift_dir.dot(span) * span;
  const double norm = lift_dir.norm();
  if (norm > 1e-12) force += q * liftCoefficient(alpha, c) * (lift_dir / norm);
  return force;
}

Wrench QuasiSteadyAirModel::bodyWrench(const BodyKinematics& body, const AeroSurface& surface,
                                       const AirParams& air, std::vector<Vec3>* cell_forces) const {
  return sumCells(body, surface, air, cell_forces,
                  [&](const Vec3& u, const SurfaceCell& cell, const Vec3& span) {
                    return quasiSteadyForce(u, cell.normal, span, cell.area, air.density,
                                            air.quasi_steady);
                  });
}

AirModelPtr makeAirModel(const std::string& name) {
  if (name == "pressure") return std::make_shared<PressureAirModel>();
  if (name == "quasi_steady") return std::make_shared<QuasiSteadyAirModel>();
  return nullptr;
}

}  // namespace flapsim
