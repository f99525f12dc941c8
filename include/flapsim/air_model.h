// The air model as pure functions plus a small interface the world calls
// once per step for every aero body. No Bullet, no ROS, no state.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/creature_model.h"
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
  /// The added mass of plate-like bodies moving along their normal (rho pi c^2 b / 4),
  /// treated implicitly (flapsim/fluid_inertia.h). On by default, in air and water: a flap
  /// unit's wing (0.22 x 0.35 m, 4 g) carries 16 g of air, four times its own mass; in water
  /// it is ~175 times, and explicit drag diverges without it. Per link:
  /// <aero link="..." added_mass="true|false"/>.
  bool added_mass = true;
  int subdivisions_u = 4;  // cells per face along its first edge
  int subdivisions_v = 4;  // ... and along its second edge
  bool enabled = true;
  /// Quasi-steady model only. The air force of a chordwise strip acts at d_cp / c =
  /// 0.82 |alpha| / pi + 0.05 from the leading edge (Whitney & Wood 2010) instead of at
  /// mid-chord. On by default: without it a translating plate has no pitching moment at all.
  bool centre_of_pressure_shift = true;
  /// Quasi-steady model only. Rotational lift C_rot rho U c^2 omega per unit span along the
  /// face normal, C_rot = pi (0.75 - x0) (Sane & Dickinson 2002). On by default: it is part of
  /// the published quasi-steady model, and zero unless the wing pitches about its span.
  bool rotational_lift = true;
};

/// The water preset: density 1000 kg/m^3 with buoyancy, otherwise as AirParams.
inline AirParams waterParams() {
  AirParams water;
  water.density = 1000.0;
  water.buoyancy = true;
  water.added_mass = true;
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
  /// Unit spanwise direction in the face plane, for the quasi-steady model: the link's span
  /// axis projected onto the face (see buildSurface), else the face's longer edge.
  Vec3 span = Vec3::UnitY();
  /// Unit chordwise direction normal x span, and the face's extent along it (coordinates of
  /// its two chordwise edges in the body frame): the chord is chord_max - chord_min.
  Vec3 chord = Vec3::UnitX();
  double chord_min = 0.0, chord_max = 0.0;
  Vec3 corners[4];
  int first_cell = 0;
  int cell_count = 0;
  /// A regular grid when nu > 0: cell (i, j) is cells[first_cell + i * nv + j], centred at
  /// cells[first_cell].centre + i * step_u + j * step_v, all of the same area. nu = 0 when
  /// some of its cells were hidden (buildSurface): the survivors are then a plain list.
  int nu = 0, nv = 0;
  Vec3 step_u = Vec3::Zero(), step_v = Vec3::Zero();
  /// For a grid, constants of its pressure sums (addBoxFaces sets them): the first cell's
  /// centre, step_u and step_v, each crossed with the normal (u.n = v.n + w.(r x n) for a
  /// body moving at v, w), and the index in AeroSurface::faces of the first face with the
  /// same step_u and step_v (the opposite faces of a box share them).
  Vec3 centre_x_normal = Vec3::Zero(), step_u_x_normal = Vec3::Zero();
  Vec3 step_v_x_normal = Vec3::Zero();
  int steps_of = -1;
};

/// The aero description of one rigid body, in its COM frame.
struct AeroSurface {
  std::vector<SurfaceCell> cells;
  std::vector<SurfaceFace> faces;  // optional: lets a model skip faces that retreat
  double drag_coefficient = 1.15;
  /// Displaced volume (the union of the boxes, overlaps counted once) and its centroid in the
  /// body frame: buoyancy acts there (buoyancyWrench).
  double volume = 0.0;
  Vec3 centroid = Vec3::Zero();
  /// A point of the axis the wing pitches about (along the span), body frame: x0 of the
  /// rotational lift is where it lies along the chord. The COM unless set.
  Vec3 pitch_axis_point = Vec3::Zero();
};

/// Adds the 6 faces of a box (size, pose in the body frame), nu x nv cells each, to
/// `surface`, and its volume: the centroid becomes the volume-weighted mean of the boxes', so
/// this is right only for boxes that do not overlap (buildSurface handles overlaps). The span
/// of each face is its longer edge.
void appendBox(AeroSurface& surface, const Vec3& size, const Pose& origin, int nu, int nv);

/// The volume and centroid of a union of boxes (body frame), overlaps counted once.
struct BoxUnion {
  double volume = 0.0;
  Vec3 centroid = Vec3::Zero();
};

/// Exact when every box is axis-aligned with the first one (any 90-degree turns) or overlaps
/// no other. Otherwise a box whose bounds overlap an earlier box's adds what of it lies outside
/// the earlier boxes, measured along 128 x 128 lines parallel to its x edge: exactly along
/// each line, by the midpoint rule across them, so the error is second order (3.5e-5 of the
/// overlap for a cube turned 45 degrees in another, see test_air).
BoxUnion unionOfBoxes(const std::vector<Box>& boxes);

/// The aero surface of a rigid body made of `boxes` (poses in the body/COM frame): the faces
/// of every box, nu x nv cells each, minus the cells whose centre lies inside another box or
/// on its surface (within 1e-6 of the largest box dimension): faces flush against or buried
/// in another box feel no air. Faces that keep all their cells keep the fast regular grid.
/// `span` (body frame, any length), projected onto each face that it is not nearly normal
/// to (at least 0.1 of it in the face plane), gives the faces' span; else the longer edge.
/// volume/centroid: unionOfBoxes. drag_coefficient and pitch_axis_point keep defaults.
AeroSurface buildSurface(const std::vector<Box>& boxes, int nu, int nv,
                         const std::optional<Vec3>& span = std::nullopt);

/// A link's boxes in its COM frame, and its cells per face edge (its AeroSettings', else the
/// world's), as its aero surface and its added mass use them.
std::vector<Box> comFrameBoxes(const LinkModel& link);
int subdivisionsU(const LinkModel& link, const AirParams& air);
int subdivisionsV(const LinkModel& link, const AirParams& air);

/// The aero surface of link `link` of `model`, as the world uses it: its boxes in its COM
/// frame, subdivisions and drag coefficient from its AeroSettings else from `air`, the span
/// of spanAxis(model, link), and the pitch axis through the link frame's origin when its
/// parent joint is a feather joint (else through the COM).
AeroSurface linkAeroSurface(const CreatureModel& model, int link, const AirParams& air);

/// World-frame kinematics of a rigid body at its centre of mass.
struct BodyKinematics {
  Quat orientation = Quat::Identity();  // body (COM) frame -> world
  Vec3 com = Vec3::Zero();
  Vec3 linear_velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
  /// Optional, when the caller has them (LinkFrames::kinematics): `orientation` as a matrix
  /// and the two velocities in the body frame, which the air models use instead of turning
  /// them again.
  bool has_body_frame = false;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Vec3 body_linear_velocity = Vec3::Zero();
  Vec3 body_angular_velocity = Vec3::Zero();
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

/// Velocity of a point at offset r from the COM relative to the air: u = v + w x r - wind
/// (the air's velocity seen from the point is -u).
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

/// Buoyancy of a body as a wrench about its COM (world frame): the force -rho V g of the
/// surface's displaced volume, acting at its centroid, so torque (R centroid) x force.
Wrench buoyancyWrench(const AeroSurface& surface, const BodyKinematics& body, double density,
                      const Vec3& gravity);

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

/// Whitney & Wood (2010): the centre of pressure of a chordwise strip at angle of attack
/// alpha (degrees, 0..90) lies d_cp / c = 0.82 alpha / 180 + 0.05 from its leading edge.
double centreOfPressureFraction(double alpha_deg);

/// Sane & Dickinson (2002): rotational force coefficient C_rot = pi (0.75 - x0), x0 the
/// pitch axis' distance from the leading edge over the chord.
double rotationalLiftCoefficient(double x0);

/// A quasi-steady blade-element model: per cell, angle of attack from the chordwise
/// velocity; lift and drag from QuasiSteadyCoefficients. Needs AeroSurface::faces.
/// With AirParams::centre_of_pressure_shift, each cell's force acts (c/2 - d_cp) ahead of the
/// cell's centre, towards the leading edge (the chordwise edge the cell moves towards), which
/// puts a uniformly loaded strip's force at d_cp. With AirParams::rotational_lift, each cell
/// of an advancing face also feels C_rot rho U c s_i omega along the face normal, where U and
/// the leading edge are taken at the pitch axis (same span station, so pure pitching about the
/// axis in still air gives none), omega is the angular velocity about the span, positive when
/// it raises the angle of attack, and the force then adds to the translational normal force.
/// Faces without span information (no AeroSurface::faces) get neither.
class QuasiSteadyAirModel : public AirModel {
 public:
  Wrench bodyWrench(const BodyKinematics& body, const AeroSurface& surface, const AirParams& air,
                    std::vector<Vec3>* cell_forces) const override;
};

using AirModelPtr = std::shared_ptr<const AirModel>;

/// The model of that name ("pressure", "quasi_steady"), or null for an unknown name.
AirModelPtr makeAirModel(const std::string& name);

}  // namespace flapsim
