// The air model as pure functions plus a small interface the world calls
// once per step for every aero body. No Bullet, no ROS, no state.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "flapsim/types.h"

namespace flapsim {

/// Lift and drag coefficients of a flat wing against the angle of attack a (degrees):
/// C_L = lift_mean + lift_amplitude sin(lift_frequency a + lift_phase),
/// C_D = drag_mean - drag_amplitude cos(drag_frequency a + drag_phase).
/// Defaults: the Robofly fits of Dickinson, Lehmann and Sane (1999).
struct QuasiSteadyCoefficients {
  double lift_mean = 0.225, lift_amplitude = 1.58, lift_frequency = 2.13, lift_phase = -7.20;
  double drag_mean = 1.92, drag_amplitude = 1.55, drag_frequency = 2.04, drag_phase = -9.82;
};

/// Air parameters of a world (per-link overrides live in AeroSettings).
struct AirParams {
  std::string model = "pressure";  // "pressure" (the paper's) or "quasi_steady"
  QuasiSteadyCoefficients quasi_steady;
  double density = 1.204;          // kg/m^3 (1000 for water)
  double drag_coefficient = 1.15;  // Cd of the paper's method
  Vec3 wind = Vec3::Zero();        // uniform wind, world frame, m/s
  bool buoyancy = true;
  int subdivisions_u = 4;  // cells per face along its first edge
  int subdivisions_v = 4;  // ... and along its second edge
  bool enabled = true;
};

/// The water preset: density 1000 kg/m^3 with buoyancy, otherwise as AirParams.
inline AirParams waterParams() {
  AirParams water;
  water.density = 1000.0;
  water.buoyancy = true;
  return water;
}

/// One sub-surface: centre and outward unit normal in the body (COM) frame.
struct SurfaceCell {
  Vec3 centre = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  double area = 0.0;
};

/// A planar face: its cells are cells[first_cell, first_cell + cell_count).
struct SurfaceFace {
  Vec3 normal = Vec3::UnitZ();
  Vec3 span = Vec3::UnitY();  // the face's longer edge (the wing span of a wing plate)
  Vec3 corners[4];
  int first_cell = 0;
  int cell_count = 0;
  /// A regular grid when nu > 0: cell (i, j) is cells[first_cell + i * nv + j], centred at
  /// cells[first_cell].centre + i * step_u + j * step_v, all of the same area.
  int nu = 0, nv = 0;
  Vec3 step_u = Vec3::Zero(), step_v = Vec3::Zero();
};

/// The aero description of one rigid body, in its COM frame.
struct AeroSurface {
  std::vector<SurfaceCell> cells;
  std::vector<SurfaceFace> faces;  // optional: lets a model skip faces that retreat
  double drag_coefficient = 1.15;
  double volume = 0.0;  // for buoyancy
};

/// Adds the 6 faces of a box (size, pose in the body frame), nu x nv cells each, and its
/// volume to `surface`.
void appendBox(AeroSurface& surface, const Vec3& size, const Pose& origin, int nu, int nv);

/// World-frame kinematics of a rigid body at its centre of mass.
struct BodyKinematics {
  Quat orientation = Quat::Identity();  // body (COM) frame -> world
  Vec3 com = Vec3::Zero();
  Vec3 linear_velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
};

/// Force and torque about the body's centre of mass, world frame.
struct Wrench {
  Vec3 force = Vec3::Zero();
  Vec3 torque = Vec3::Zero();
  Wrench& operator+=(const Wrench& o) {
    force += o.force;
    torque += o.torque;
    return *this;
  }
};

/// Splits each of the 6 faces of a box (size, pose in the body frame) into an
/// nu x nv grid of cells.
std::vector<SurfaceCell> boxSurfaceCells(const Vec3& size, const Pose& origin, int nu, int nv);

/// Velocity of the air relative to a point at offset r (world) from the COM:
/// u = v + w x r - wind.
inline Vec3 relativeAirVelocity(const Vec3& v, const Vec3& w, const Vec3& r, const Vec3& wind) {
  return v + w.cross(r) - wind;
}

/// The paper's pressure on one cell (world frame): zero unless the face
/// advances into the air (u.n > 0), then -1/2 rho Cd s |u| (u.n) n.
inline double pressureMagnitude(const Vec3& u, const Vec3& n, double area, double density,
                                double cd) {
  const double un = u.dot(n);
  return un > 0.0 ? 0.5 * density * cd * area * u.norm() * un : 0.0;
}
inline Vec3 pressureForce(const Vec3& u, const Vec3& n, double area, double density, double cd) {
  return -pressureMagnitude(u, n, area, density, cd) * n;
}

/// Buoyancy rho V g opposite to gravity (gravity is a vector, e.g. (0,0,-9.81)).
inline Vec3 buoyancyForce(double volume, double density, const Vec3& gravity) {
  return -density * volume * gravity;
}

/// An air model maps a body's motion to the wrench the air exerts on it.
/// Implementations must be pure: same inputs, same output.
class AirModel {
 public:
  virtual ~AirModel() = default;
  /// `cell_forces`, if given, receives one world-frame force per cell.
  virtual Wrench bodyWrench(const BodyKinematics& body, const AeroSurface& surface,
                            const AirParams& air, std::vector<Vec3>* cell_forces) const = 0;
};

/// The paper's model (IEEE SMC 2010, eq. 3): pressure on advancing sub-surfaces.
class PressureAirModel : public AirModel {
 public:
  Wrench bodyWrench(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air,
                    std::vector<Vec3>* cell_forces) const override;
};

/// Angle of attack in [0, 90] deg of a face with normal n moving at u (spanwise part of u
/// removed), and the lift and drag coefficients there.
double angleOfAttack(const Vec3& u_chordwise, const Vec3& n);
double liftCoefficient(double alpha_deg, const QuasiSteadyCoefficients& c);
double dragCoefficient(double alpha_deg, const QuasiSteadyCoefficients& c);

/// Quasi-steady blade-element force on one cell of an advancing face (zero otherwise):
/// with u' = u minus its component along the span s, drag 1/2 rho s_i C_D |u'|^2 against
/// u' and lift 1/2 rho s_i C_L |u'|^2 perpendicular to u' in the chord plane, on the side
/// the face pushes the air from (-n).
Vec3 quasiSteadyForce(const Vec3& u, const Vec3& n, const Vec3& span, double area, double density,
                      const QuasiSteadyCoefficients& c);

/// A quasi-steady blade-element model: per cell, angle of attack from the chordwise
/// velocity; lift and drag from QuasiSteadyCoefficients. Needs AeroSurface::faces.
class QuasiSteadyAirModel : public AirModel {
 public:
  Wrench bodyWrench(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air,
                    std::vector<Vec3>* cell_forces) const override;
};

using AirModelPtr = std::shared_ptr<const AirModel>;

/// The model of that name ("pressure", "quasi_steady"), or null for an unknown name.
AirModelPtr makeAirModel(const std::string& name);

}  // namespace flapsim
