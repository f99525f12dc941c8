#include "fluid/quasi_steady.h"

#include <algorithm>
#include <cmath>

#include "fluid/body_flow.h"

namespace flapsim {

namespace {

constexpr double kDeg = M_PI / 180.0;

}  // namespace

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

namespace {

// quasiSteadyForce, and the angle of attack in degrees in *alpha_deg when the force is not
// zero.
Vec3 quasiSteadyForceAt(const Vec3& u, const Vec3& n, const Vec3& span, double area, double density,
                        const QuasiSteadyCoefficients& c, double* alpha_deg) {
  // Edge-on within rounding counts as edge-on: C_D(0) > 0 would otherwise give a full
  // face's drag to whichever face rounding happens to tilt forward.
  if (u.dot(n) <= 1e-12 * u.norm()) return Vec3::Zero();
  const Vec3 chordwise = u - u.dot(span) * span;
  const double speed2 = chordwise.squaredNorm();
  if (speed2 == 0.0) return Vec3::Zero();
  const Vec3 drag_dir = -chordwise / std::sqrt(speed2);
  const double alpha = angleOfAttack(chordwise, n);
  *alpha_deg = alpha;
  const double q = 0.5 * density * area * speed2;
  Vec3 force = q * dragCoefficient(alpha, c) * drag_dir;
  Vec3 lift_dir = -n - (-n).dot(drag_dir) * drag_dir;  // -n without its part along the flow
  lift_dir -= lift_dir.dot(span) * span;
  const double norm = lift_dir.norm();
  if (norm > 1e-12) force += q * liftCoefficient(alpha, c) * (lift_dir / norm);
  return force;
}

}  // namespace

Vec3 quasiSteadyForce(const Vec3& u, const Vec3& n, const Vec3& span, double area, double density,
                      const QuasiSteadyCoefficients& c) {
  double alpha = 0.0;
  return quasiSteadyForceAt(u, n, span, area, density, c, &alpha);
}

double centreOfPressureFraction(double alpha_deg) {
  return 0.82 * std::abs(alpha_deg) / 180.0 + 0.05;
}

double rotationalLiftCoefficient(double x0) { return M_PI * (0.75 - x0); }

Wrench quasiSteadyLaw(const FluidInput& in, std::vector<Vec3>* cell_forces) {
  const BodyKinematics& body = in.body;
  const AeroSurface& surface = in.surface;
  const AirParams& air = in.air;
  if (surface.faces.empty()) {
    return sumCells(body, surface, air, cell_forces,
                    [&](const Vec3& u, const SurfaceCell& cell, const Vec3& span) {
                      return quasiSteadyForce(u, cell.normal, span, cell.area, air.density,
                                              air.quasi_steady);
                    });
  }
  const BodyFlow flow(body, air);
  Vec3 total = Vec3::Zero(), torque = Vec3::Zero();
  if (cell_forces) cell_forces->assign(surface.cells.size(), Vec3::Zero());
  for (const SurfaceFace& face : surface.faces) {
    if (!flow.advances(face)) continue;
    const Vec3 &n = face.normal, &s = face.span, &e = face.chord;
    const double chord = face.chord_max - face.chord_min;
    const double axis = surface.pitch_axis_point.dot(e);  // the pitch axis' chord coordinate
    // Turning about n x e raises the angle of attack of this face when it advances towards +e
    // (and lowers it towards -e).
    const double spin = flow.w.dot(n.cross(e));
    const bool rotational = air.rotational_lift && chord > 0.0 && spin != 0.0;
    for (int i = face.first_cell; i < face.first_cell + face.cell_count; ++i) {
      const SurfaceCell& cell = surface.cells[i];
      const Vec3 u = flow.at(cell.centre);
      double alpha = 0.0;
      Vec3 f = quasiSteadyForceAt(u, n, s, cell.area, air.density, air.quasi_steady, &alpha);
      if (f.isZero(0.0)) continue;
      Vec3 at = cell.centre;
      if (air.centre_of_pressure_shift && chord > 0.0) {
        const Vec3 chordwise = u - u.dot(s) * s;
        const double ahead = chordwise.dot(e);  // > 0: the leading edge is on the +e side
        if (ahead != 0.0) {
          at += (0.5 - centreOfPressureFraction(alpha)) * chord * std::copysign(1.0, ahead) * e;
        }
      }
      torque += at.cross(f);
      if (rotational) {
        // The strip's motion at the pitch axis: its speed U, and its leading edge.
        const Vec3 p = cell.centre + (axis - cell.centre.dot(e)) * e;
        Vec3 up = flow.at(p);
        up -= up.dot(s) * s;
        const double ahead = up.dot(e);
        if (ahead != 0.0) {
          const double sign = std::copysign(1.0, ahead);
          const double x0 =
              sign > 0.0 ? (face.chord_max - axis) / chord : (axis - face.chord_min) / chord;
          const Vec3 rot = -rotationalLiftCoefficient(x0) * air.density * up.norm() * chord *
                           cell.area * sign * spin * n;
          f += rot;
          torque += cell.centre.cross(rot);
        }
      }
      total += f;
      if (cell_forces) (*cell_forces)[i] = flow.rot * f;
    }
  }
  return Wrench{flow.rot * total, flow.rot * torque};
}

double QuasiSteadyAirModel::forceCoefficient(const AeroSurface& /*surface*/,
                                             const AirParams& air) const {
  const QuasiSteadyCoefficients& c = air.quasi_steady;
  return std::abs(c.lift_mean) + std::abs(c.lift_amplitude) + std::abs(c.drag_mean) +
         std::abs(c.drag_amplitude);
}

std::string QuasiSteadyAirModel::check(const AirParams& air) const {
  const QuasiSteadyCoefficients& q = air.quasi_steady;
  for (double c : {q.lift_mean, q.lift_amplitude, q.lift_frequency, q.lift_phase, q.drag_mean,
                   q.drag_amplitude, q.drag_frequency, q.drag_phase}) {
    if (!std::isfinite(c) || std::abs(c) > 1e3) {
      return "air quasi_steady coefficients must be finite and within +-1000";
    }
  }
  return "";
}

}  // namespace flapsim
