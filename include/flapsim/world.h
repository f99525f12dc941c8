// World: a Bullet multibody world of creatures, stepped at a fixed step (a step in which a
// wing reverses is taken in substeps, see turn_substep) with the air applied in every
// (sub)step. The stages of a step: src/core/world/creature_step.h. Owns sim time; never
// reads a clock.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/air_model.h"
#include "flapsim/creature_model.h"
#include "flapsim/step_data.h"
#include "flapsim/stroke.h"
#include "flapsim/types.h"

namespace flapsim {

/// How World::power takes a motor's work over a (sub)step.
enum class MotorWorkMeter {
  /// The torque its joint transmits, from the momentum the bodies beyond it (and the fluid
  /// their plates carry) gain over the (sub)step less the external impulses on them (the
  /// joint's spring and damping taken out), times the joint's move: second order in the step.
  /// Metered as kServoImpulse: a (sub)step in which a contact or a joint limit may have acted,
  /// and a creature whose plates carry added mass in a fluid without its velocity products
  /// (AirParams::added_mass_products omitted; there the
  /// momentum balance hands the bodies, as one rigid correction, the turning of the
  /// fluid's impulse that no force on the plates carries, and each joint would take a share of
  /// it: 2 % of hover_1's stroke power).
  kTransmitted,
  /// The servo's impulse times the mean of the joint's start and end velocities: it also
  /// carries the explicit step's velocity-product error, which the servo takes out to hold
  /// its rate (first order: the flap unit's positive work 1.0 % low at 1 ms, hover_1's 3.5 %).
  /// What the controllers evolved before the transmitted meter were selected on.
  kServoImpulse,
};

/// Why a motor-work flag is refused without the added mass's velocity products (appended to
/// the flag's name): in air with added mass the servo's impulse is taken either way.
constexpr const char* kMotorWorkWithoutProducts =
    " has no effect with the added mass's products omitted (--added-mass-products omitted): in "
    "a fluid whose plates carry added mass the servo's impulse is taken either way";

/// "transmitted" or "servo" (MotorWorkMeter); false for anything else.
bool motorWorkMeterFromName(const std::string& name, MotorWorkMeter* out);
const char* motorWorkMeterName(MotorWorkMeter meter);

struct WorldParams {
  double step_size = 0.001;  // s, fixed
  /// A step in which a wing's stroke turns, or whose stroke servo was saturated in the
  /// last step (the wing reversing under its effort limit), is taken in equal substeps of
  /// at most this (s; 0: never). First-order steps resolve the reversal poorly: without it
  /// the flap unit (2 N m, no added mass) climbed 5.6% less in 3 s at 1 ms than at 0.125 ms.
  /// 0.5 ms: with added mass the flap unit's 3 s climb at 1 ms is within 0.5% of 0.125 ms's
  /// at 60/10/0.8 and 50/12/0.6 (0.06% and 0.7% at 0.25 ms), for 18% fewer instructions on
  /// the 12-unit chain; a 4-unit chain at 60/10, its 2 N m motors saturated, is 2.5% off at
  /// 1 ms after 1 s (1.7% at 0.25 ms).
  double turn_substep = 0.0005;
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);
  bool ground = true;  // flat ground, top face at z = 0, 2 km x 2 km, with contact
  double ground_friction = 0.8;
  AirParams air;
  int solver_iterations = 10;
  /// A step in which no link can reach the ground skips Bullet's collision, island and
  /// constraint-solver stages, which find nothing then (unless a joint nears its limit), and
  /// updates the velocities in the world frame instead of Bullet's link frames: the same
  /// trajectory up to rounding, in less time. Off: every step is Bullet's full step.
  bool lean_steps = true;
  /// Threads that step creatures in parallel (results do not depend on it). Creatures
  /// live in Bullet worlds of their own: they touch the ground but not one another.
  int threads = 1;
  double default_wing_effort = 5.0;  // N m, when a wing joint has no URDF effort limit
  /// The divergence watchdog: a creature with a point of a link faster than this (m/s), or
  /// with a non-finite state, is frozen (see World::divergence).
  double max_speed = 1000.0;
  /// Air cells a creature may have (boxes x 6 faces x subdivisions, over its aero links):
  /// a spawn or an air change beyond it is refused, naming the creature and its links.
  int max_cells = 200000;
  /// How the motors' work (World::power, StepData::joint_power) is taken.
  MotorWorkMeter motor_work = MotorWorkMeter::kTransmitted;
};

/// Largest magnitudes a world accepts: a position or wind component, gravity, density.
constexpr double kMaxPosition = 1e6;  // m
constexpr double kMaxGravity = 1e4;   // m/s^2
constexpr double kMaxDensity = 1e5;   // kg/m^3
constexpr double kMaxDragCoefficient = 1e3;
constexpr double kMaxSpin = 1e5;  // rad/s, of a spawned creature

/// Empty string if valid, else a message naming the bad parameter.
std::string validateWorldParams(const WorldParams& params);

/// Joint damping and <spring> stiffness act as explicit torques up to a quarter of the child
/// link's own inertia about the axis per step (damping) or per step squared (stiffness), beyond
/// which an explicit step would blow up; a joint with either beyond has both act implicitly,
/// in the servo solve (backward Euler: unconditionally stable, its motion faster than the step
/// damped out). One line per URDF value beyond, naming the joint, the value and the limit;
/// empty if every joint is explicit. (The simulator node logs these lines.)
std::vector<std::string> implicitJointValues(const CreatureModel& model, double step_size);

/// State of one creature. Vectors follow the model's links / joints.
struct CreatureState {
  std::vector<Pose> link_poses;          // URDF link frames in the world
  std::vector<Twist> link_twists;        // velocity of each link frame's origin, world frame
  std::vector<double> joint_positions;   // per model joint (0 for fixed joints)
  std::vector<double> joint_velocities;  // per model joint (0 for fixed joints)
  /// Per model joint: the torque (force, if prismatic) its servo applied in the last step
  /// (wing motor, velocity target, feathering or Coulomb friction; not damping).
  std::vector<double> joint_efforts;
};

/// The pose and twist (CreatureState's conventions) of frame `name` of a creature of `model`
/// in `state`: a link's (empty: the root's) or a lumped link's (CreatureModel::lumped, fixed to
/// the link it is lumped into). False, and nothing set, if the creature has no such frame.
bool frameMotion(const CreatureModel& model, const CreatureState& state, const std::string& name,
                 Pose* pose, Twist* twist);

/// The mechanical power of a creature's motors (World::power): each motor's torque times its
/// joint's displacement, step by step (substeps included), summed since the creature was
/// spawned or the world reset. A motor is a joint driven by a stroke, a velocity target or a
/// stroking wing's feathering; passive joints (damping, friction, springs) are not motors.
/// Vectors follow the model's joints (0 for joints without a motor).
struct CreaturePower {
  double time = 0.0;  // s of steps counted
  double mass = 0.0;  // kg, the creature's
  /// W: each motor's mean power over the last step (> 0: driving its joint, < 0: braking it).
  std::vector<double> power;
  std::vector<double> work;           // J: net work
  std::vector<double> positive_work;  // J: the sum of the steps' positive work
  double totalPower() const;
  double totalWork() const;
  double totalPositiveWork() const;
  /// W: total positive work over the time (0 before the first step): what motors that cannot
  /// recover braking energy deliver, on average.
  double meanPositivePower() const;
};

/// The energy audit of a creature (World::setEnergyAudit, World::energy), in the frame of the
/// fluid (velocities relative to the world's wind, which must stay steady for the balance):
/// the energies of its state, and the works done on it since it was spawned or the world
/// reset, the air's and the damping's counted only while the audit is on. Balance:
/// motor_work + air_work + damping_work = change of total(), up to residual() (the step's
/// error, and what no term counts: joint limits, contacts, friction, external wrenches).
struct CreatureEnergy {
  double kinetic = 0.0;        // J, of the bodies
  double potential = 0.0;      // J, in gravity, -m g . x over the links (0 at the origin)
  double spring = 0.0;         // J, of the <spring> joints (their stiffness as the step uses it)
  double fluid_kinetic = 0.0;  // J, of the fluid the plates carry: 1/2 nu^T A nu per plate
  double motor_work = 0.0;     // J, World::power's net work
  double air_work = 0.0;       // J, of the air's forces (pressure, buoyancy, implicit drag)
  double damping_work = 0.0;   // J, of the passive joints' damping (<= 0)
  double total() const { return kinetic + potential + spring + fluid_kinetic; }
  /// The works since `start` less the change of total() since it.
  double residual(const CreatureEnergy& start) const {
    return (motor_work - start.motor_work) + (air_work - start.air_work) +
           (damping_work - start.damping_work) - (total() - start.total());
  }
};

/// A state to put a creature in (World::setState), world frame. The pose and twist are those
/// of one link's URDF frame, or a lumped link's (CreatureState's convention: the twist is the
/// velocity of the frame's origin); the rest of the creature follows through its joints.
struct StateRequest {
  std::string link;  // empty: the root link
  Pose pose;
  Twist twist;
  /// Empty: the joints keep their positions (velocities); else one value per model joint,
  /// in model order (fixed joints' values must be 0).
  std::vector<double> joint_positions;
  std::vector<double> joint_velocities;
};

/// A wrench applied to a link from outside (World::applyWrench): a push or a gust.
struct ExternalWrench {
  std::string link;            // empty: the root link; a lumped link: the link it is lumped into
  Vec3 force = Vec3::Zero();   // N, world frame
  Vec3 torque = Vec3::Zero();  // N m, world frame, added to the force's moment
  Vec3 point = Vec3::Zero();   // where the force acts, world frame, at the time of the call
  double duration = 0.0;       // s of sim time (whole steps); < 0: until cleared
  /// s of sim time: it acts from the first step that starts at or after it (within
  /// kWrenchStartTolerance), its duration counted from there; 0 or a time already passed: from
  /// the next step. Force, torque and point are still taken at the call.
  double start_time = 0.0;
};

/// Largest magnitudes of an external wrench, its longest duration, and the most wrenches
/// acting on one creature at a time.
constexpr double kMaxForce = 1e6;           // N
constexpr double kMaxTorque = 1e6;          // N m
constexpr double kMaxWrenchDuration = 1e9;  // s
constexpr int kMaxWrenches = 1000;
/// A step starting this close before a wrench's start_time counts as starting at it.
constexpr double kWrenchStartTolerance = 1e-9;  // s

/// Last air wrench on each link (about its COM), and optionally per cell.
struct LinkAero {
  int link = -1;
  Vec3 com = Vec3::Zero();
  Wrench wrench;
  std::vector<Vec3> cell_centres;  // world, only if cell output is enabled
  std::vector<Vec3> cell_forces;
};

/// The wing joints that `commands` address (`joints` empty: every wing joint, in URDF
/// order), checked: throws InputError naming an unknown or non-wing joint, a count that does
/// not match, a bad stroke, or an amplitude that does not fit inside the joint's limits.
/// World::setWingCommands uses it; a caller commanding several creatures at once can check
/// them all first.
std::vector<int> checkWingCommands(const CreatureModel& model,
                                   const std::vector<std::string>& joints,
                                   const std::vector<StrokeCommand>& commands);

/// One creature's wing command (World::setWingCommands): `joints` empty = every wing joint in
/// URDF order.
struct CreatureWingCommand {
  std::string creature;
  std::vector<std::string> joints;
  std::vector<StrokeCommand> strokes;
};

/// What the world does with a creature's wing joints once no wing command came for a while
/// (World::setCommandTimeout): a guard against a controller that stopped.
struct CommandTimeout {
  enum class Action {
    kHold,    // the wing motors hold the wings where they are (World::holdJoint)
    kRelease  // the wing motors let go: the wing joints are passive (World::clearJointCommand)
  };
  /// s of sim time after a creature's last wing command at which its wings are held or
  /// released, until the next command: rounded to whole steps, at least one; 0: never.
  double seconds = 0.0;
  Action action = Action::kHold;
};
/// The longest command timeout (s).
constexpr double kMaxCommandTimeout = 1e6;

/// A creature whose wing command timed out (World::commandLapse, World::takeCommandLapses).
struct CommandLapse {
  std::string creature;
  std::uint64_t commanded_step = 0;  // the step count when its last wing command came
  std::uint64_t step = 0;            // the step count at which it timed out
};

class CommandTimeouts;

/// Why the watchdog froze a creature: the step whose result it refused and the quantity at
/// fault, e.g. "link 'wing' moves at 1.7e+06 m/s (max_speed 1000 m/s)".
struct Divergence {
  std::string creature;
  std::uint64_t step = 0;
  std::string quantity;
};

class World {
 public:
  /// Throws InputError if the parameters are invalid.
  explicit World(const WorldParams& params = WorldParams());
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// Adds a creature at `pose` (its URDF root link's frame, as Gazebo's model frame: also when
  /// that link is massless and lumped into the link it is fixed to) moving with `twist` (of
  /// that frame's origin). Throws InputError for a taken or empty name or a non-finite pose.
  void spawn(const std::string& name, CreatureModelPtr model, const Pose& pose,
             const Twist& twist = Twist());
  /// Removes a creature; InputError if unknown.
  void remove(const std::string& name);
  bool has(const std::string& name) const;
  std::vector<std::string> creatureNames() const;  // in spawn order
  CreatureModelPtr model(const std::string& name) const;

  /// Puts every creature back to its spawn pose and twist, restarts every stroke (wing
  /// commands are kept: a creature whose command timed out gets it back, its timeout
  /// starting again at 0) and sets time to zero: bit-identical to a freshly built world
  /// given the same commands.
  void reset();
  /// Advances `steps` fixed steps. A creature whose state after a step would be non-finite
  /// or faster than `max_speed` anywhere keeps the state before that step and is not stepped
  /// again until reset() (it is "frozen", its joint efforts zero: nothing drives it); the
  /// others go on. A wing-command timeout (setCommandTimeout) lapses at the step it falls due,
  /// however many steps are asked for at a time.
  void step(int steps = 1);
  /// The watchdog's verdict on a creature: none while it runs normally.
  std::optional<Divergence> divergence(const std::string& creature) const;
  /// Creatures frozen since the last call, each reported once, in the order found.
  std::vector<Divergence> takeDivergences();
  double time() const;
  std::uint64_t stepCount() const;
  const WorldParams& params() const;

  /// Replaces the air parameters (validated first) or the air model.
  void setAirParams(const AirParams& air);
  void setAirModel(AirModelPtr model);
  /// Replaces gravity (finite, at most 1e4 m/s^2, else InputError) from the next step on.
  void setGravity(const Vec3& gravity);

  /// Commands wing joints. `joints` empty = all wing joints in URDF order.
  /// All-or-nothing: on any bad joint name, length or value, throws
  /// InputError naming it and changes nothing. Starts the creature's command timeout again.
  void setWingCommands(const std::string& creature, const std::vector<std::string>& joints,
                       const std::vector<StrokeCommand>& commands) {
    setWingCommands({CreatureWingCommand{creature, joints, commands}});
  }
  /// Commands several creatures at once, all or nothing: each creature known and named once,
  /// each command checked (checkWingCommands) before any is applied. Throws InputError naming
  /// the creature and the cause, and changes nothing.
  void setWingCommands(const std::vector<CreatureWingCommand>& commands);
  /// The wing-command timeout of every creature (CommandTimeout; none at first), from the
  /// next step on. InputError unless 0 <= seconds <= kMaxCommandTimeout.
  void setCommandTimeout(const CommandTimeout& timeout);
  /// The lapse of a creature's wing command while its wings are held or released for want
  /// of one: none while it is commanded, or was never.
  std::optional<CommandLapse> commandLapse(const std::string& creature) const;
  /// The lapses since the last call, each once, in the order they fell due.
  std::vector<CommandLapse> takeCommandLapses();
  /// Raw joint-velocity target on a movable joint (replaces a stroke there).
  void setJointVelocityTarget(const std::string& creature, const std::string& joint,
                              double velocity);
  /// Holds a movable joint at its present angle with its motor (within its effort), until
  /// another command: a servo towards that angle, which a load does not make creep.
  void holdJoint(const std::string& creature, const std::string& joint);
  /// Stops driving a joint: it becomes passive.
  void clearJointCommand(const std::string& creature, const std::string& joint);
  /// Current stroke command of a wing joint (zero if none).
  StrokeCommand wingCommand(const std::string& creature, const std::string& joint) const;

  CreatureState state(const std::string& creature) const;
  /// Puts a creature in a state: `request.link` at `request.pose` moving with
  /// `request.twist`, with the joints as they are or as given. Strokes, commands and time go
  /// on; a creature the watchdog froze runs again. Throws InputError naming the culprit (an
  /// unknown creature or link, a non-finite or out-of-range value, a wrong count, a joint
  /// position outside its limits, a moving fixed base) and changes nothing.
  void setState(const std::string& creature, const StateRequest& request);
  /// Applies `wrench` to a link of a creature from the next step on, or from the first step
  /// that starts at or after its start_time, for round(duration / step_size) steps (at least
  /// one: a duration shorter than a step, 0 included, acts for one step, as in
  /// gazebo_msgs/ApplyBodyWrench; at most kMaxWrenchDuration; < 0: until cleared). The point
  /// moves with the link from the call on; the directions stay fixed in the world. Counted in
  /// the momentum balance like the air. At most kMaxWrenches act or wait on a creature at a
  /// time. Returns the sim time of the step it acts from (if the step size stays). Throws
  /// InputError naming the culprit and changes nothing.
  double applyWrench(const std::string& creature, const ExternalWrench& wrench);
  /// Removes the external wrenches of a creature (empty: of every creature), and of one of
  /// its links only if `link` is given. Returns how many were removed.
  int clearWrenches(const std::string& creature = "", const std::string& link = "");
  /// External wrenches still acting on a creature, or waiting for their start_time.
  int wrenchCount(const std::string& creature) const;
  /// Acceleration of the root link's centre of mass over the last step, world frame (zero
  /// before the first step after a spawn, reset or setState, and while frozen).
  Vec3 rootAcceleration(const std::string& creature) const;
  /// The air's velocity at the creature's root COM now, world frame: the steady wind, the
  /// discrete gust and the creature's realisation of the turbulence (AirParams), which its
  /// next step feels uniformly over its links.
  Vec3 airVelocity(const std::string& creature) const;
  /// The mechanical power and work of the creature's motors (see CreaturePower).
  CreaturePower power(const std::string& creature) const;
  /// Pose of the root link frame and the twist of the root link frame's origin (world frame;
  /// CreatureState's convention), which is not its centre of mass's unless the two coincide.
  Pose rootPose(const std::string& creature) const;
  Twist rootTwist(const std::string& creature) const;

  /// Records per-cell forces for aeroForces() (costs time; off by default).
  void setRecordCellForces(bool on);
  /// Counts the air's and the damping's work for energy() (costs time; off by default).
  void setEnergyAudit(bool on);
  /// The energy audit of a creature (see CreatureEnergy).
  CreatureEnergy energy(const std::string& creature) const;
  /// Air wrenches of the last step, one entry per aero link: the explicit air force on the
  /// body and the fluid it carries (the pressure or quasi-steady law, buoyancy, and in the shed
  /// air the velocity products the plate sheds, the mean of the step's start and end), not the
  /// added mass's reaction inside them (-A dnu) nor the implicit drag.
  std::vector<LinkAero> aeroForces(const std::string& creature) const;
  /// The named outputs of the creature's last step, as its stages wrote them (see StepData).
  StepData stepData(const std::string& creature) const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
  std::unique_ptr<CommandTimeouts> timeouts_;  // the wing-command timeout's policy
};

}  // namespace flapsim
