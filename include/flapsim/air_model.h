// The air's public face: its parameters, the surface and motion of a rigid body that an air
// model reads, and the interface of an air model (the world calls it for every aero body in
// every (sub)step; a model of your own is one class, given to World::setAirModel). The
// built-in laws (pressure, quasi-steady, buoyancy, added mass) are pure functions in
// src/core/fluid/. No Bullet, no ROS, no state.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/creature_model.h"
#include "flapsim/turbulence.h"
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
/// What a plate's added mass A does beyond -A dnu, the part of its acceleration relative to the
/// fluid that the implicit solve's joint-rate velocity change holds (AirParams::
/// added_mass_products, air/added_mass_products, --added-mass-products).
enum class AddedMassProducts {
  /// Nothing more: the bias b of the acceleration (the root's -w x v, each joint's v_parent x
  /// v_child) and the velocity products are left out. The air the controllers evolved before 7
  /// December 2026 flew in (their files say so); its energy does not balance: the audit misses
  /// by 1-5 % of the motors' positive work in air and 20-40 % in water at any step.
  kOmitted,
  /// Kirchhoff's equations: each plate -(A b + nu x* A nu) of its motion nu relative to the
  /// fluid, and the creature's angular momentum carried with the Munk term. Body and fluid keep
  /// their energy (the audit within 0.3 % at 1 ms); the flap unit turns over in pitch.
  kKirchhoff,
  /// Kirchhoff's air less each plate's products nu x* A nu and the creature's Munk term, which
  /// the wake takes: a plate feels -A dnu/dt in its own frame, the quasi-steady added mass of
  /// flapping-wing models (Sane & Dickinson 2002, Whitney & Wood 2010). The products do no work
  /// on the plate, so body and fluid keep their energy (the audit within 0.3 % at 1 ms, first
  /// order in the step), and no Munk moment turns the flap unit over. The default.
  kShed,
};

/// "omitted", "kirchhoff", "shed".
const char* addedMassProductsName(AddedMassProducts products);
/// The three names, in the enum's order.
std::vector<std::string> addedMassProductsNames();
/// The one named `name`; throws InputError naming it and the choices otherwise.
AddedMassProducts parseAddedMassProducts(const std::string& name);

struct AirParams {
  std::string model = "pressure";  // "pressure" (the paper's) or "quasi_steady"
  QuasiSteadyCoefficients quasi_steady;
  double density = 1.204;          // kg/m^3 (1000 for water)
  double drag_coefficient = 1.15;  // Cd of the paper's method
  Vec3 wind = Vec3::Zero();        // uniform wind, world frame, m/s
  /// Dryden turbulence and a discrete gust on top of the steady wind (flapsim/turbulence.h),
  /// sampled per creature at the start of each step; off by default.
  TurbulenceParams turbulence;
  DiscreteGust gust;
  bool buoyancy = true;
  /// The added mass of plate-like bodies moving along their normal (rho pi c^2 b / 4),
  /// treated implicitly (flapsim/fluid_inertia.h). On by default, in air and water: a flap
  /// unit's wing (0.22 x 0.35 m, 4 g) carries 16 g of air, four times its own mass; in water
  /// it is ~175 times, and explicit drag diverges without it. Per link:
  /// <aero link="..." added_mass="true|false"/>.
  bool added_mass = true;
  /// What the plates' added mass does beyond the implicit solve's -A dnu (AddedMassProducts):
  /// by default the products shed into the wake, the air whose energy balances and whose flap
  /// unit does not turn over in pitch (doc/physics.md).
  AddedMassProducts added_mass_products = AddedMassProducts::kShed;
  /// Whether the plates' added mass takes the acceleration's bias and Kirchhoff's velocity
  /// products (some of them shed or not).
  bool addedMassVelocityProducts() const {
    return added_mass_products != AddedMassProducts::kOmitted;
  }
  /// Whether the plates shed their velocity products into the wake.
  bool shedProducts() const { return added_mass_products == AddedMassProducts::kShed; }
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

/// Velocity of a point at offset r from the COM relative to the air: u = v + w x r - wind
/// (the air's velocity seen from the point is -u).
inline Vec3 relativeAirVelocity(const Vec3& v, const Vec3& w, const Vec3& r, const Vec3& wind) {
  return v + w.cross(r) - wind;
}

/// How the world treats an air model's drag where it is stiff (a drag rate of more than two
/// link masses per step, from AirModel::forceCoefficient): in the velocity update, as a
/// damping over half the step (the trapezoidal rule), besides the force evaluated at the
/// step's start.
enum class AirLinearisation {
  kNone,              // never: the law is evaluated explicitly only, stiff or not
  kOwn,               // with the law's own derivative, AirModel::dragDamping
  kFiniteDifference,  // with central differences of AirModel::bodyWrench (12 calls)
};

/// 6x6 about a body's centre of mass, world axes, [angular; linear].
using AirDamping = Eigen::Matrix<double, 6, 6>;

/// An air model (a fluid law) maps a body's motion to the wrench the air exerts on it: its
/// contract is its force kernel (bodyWrench, pure: same inputs, same output), its
/// linearisation for the implicit solve (or none, stated), the scale of its forces that decides
/// when it is stiff, the parameters it reads and their checks. A law of your own is one class
/// and one registerAirModel line (then `<aero model="name">` and AirParams::model take it), or
/// World::setAirModel for one world.
class AirModel {
 public:
  virtual ~AirModel() = default;
  /// `cell_forces`, if given, receives one world-frame force per cell.
  virtual Wrench bodyWrench(const BodyKinematics& body, const AeroSurface& surface,
                            const AirParams& air, std::vector<Vec3>* cell_forces) const = 0;
  /// How the world treats the law where it is stiff (see AirLinearisation). Default: kNone.
  virtual AirLinearisation linearisation() const { return AirLinearisation::kNone; }
  /// For kOwn: the damping D, symmetric positive semi-definite, by which the wrench changes by
  /// about -D dnu for a change dnu = [d omega; d v] of the body's motion relative to the air.
  virtual AirDamping dragDamping(const BodyKinematics& body, const AeroSurface& surface,
                                 const AirParams& air) const;
  /// C such that the law's force on the body is at most about 1/2 rho C A |u|^2 (A: its cells'
  /// area, |u|: its fastest point's speed relative to the air): the world's stiffness test.
  /// Default: the surface's drag coefficient.
  virtual double forceCoefficient(const AeroSurface& surface, const AirParams& air) const;
  /// Whether the law's force on every cell lies along the cell's normal (the paper's pressure
  /// law): the stiffness test then counts, besides the link's own mass, the added mass its
  /// plates carry along their normals, which the velocity update holds implicitly. Default:
  /// false (the test counts the link's own mass only).
  virtual bool forcesAlongNormals() const { return false; }
  /// Whether the law reads AirParams::drag_coefficient (the surface's Cd). Default: false.
  virtual bool readsDragCoefficient() const { return false; }
  /// Empty if the parameters the law reads are valid, else a message naming the bad one. The
  /// world checks every registered law's parameters with the air's. Default: "".
  virtual std::string check(const AirParams& air) const;
};

using AirModelPtr = std::shared_ptr<const AirModel>;

/// The registered model of that name ("pressure", "quasi_steady", or one registerAirModel
/// added), or null for an unknown name. Models are pure, so one instance serves every world.
AirModelPtr makeAirModel(const std::string& name);

/// Adds a law that links (`<aero model="name">`) and AirParams::model can name, for every world
/// created afterwards. Throws InputError if the name is empty, taken, or the model null.
void registerAirModel(const std::string& name, AirModelPtr model);

/// Names of the registered air models: the built-in ones first, {"pressure", "quasi_steady"},
/// then the registered ones in order: the one list that validation, error messages and per-link
/// model lookups derive from.
std::vector<std::string> airModelNames();

/// "unknown air model '<name>' (pressure, quasi_steady)", the list taken from airModelNames().
std::string unknownAirModelMessage(const std::string& name);

/// The first failing check of every registered law (AirModel::check), or "".
std::string checkAirModels(const AirParams& air);

}  // namespace flapsim
