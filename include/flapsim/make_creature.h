// Generator of flapping creatures: N flap units chained by passive joints.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "flapsim/cli_args.h"

namespace flapsim {

/// The axis of a passive joint between two units (x: roll, y: pitch).
enum class LinkAxis { kRoll, kPitch };
/// "roll" or "pitch"; std::invalid_argument naming the text otherwise.
LinkAxis linkAxisFromString(const std::string& text);
std::string toString(LinkAxis axis);

/// Dimensions and masses of one flapping unit (body + two wing plates).
struct FlapUnitParams {
  double body_length = 0.08;  // along x (forward)
  double body_width = 0.06;   // along y
  double body_height = 0.03;  // along z
  double body_mass = 0.015;
  /// The body's centre of mass lies this far below the wing hinges (a ballast under the
  /// body; the box stays where it is). Without it the unit is unstable in pitch: from a
  /// 0.1 rad pitch at 40/10/1.2 it drifts forward and pitches 30 deg within 6 s; with 2 cm
  /// it levels out (doc/flight_and_evolution.md).
  double body_com_drop = 0.02;
  double wing_span = 0.35;   // along y, from the hinge to the tip
  double wing_chord = 0.22;  // along x
  double wing_thickness = 0.002;
  double wing_mass = 0.004;
  /// N m, the hinge motor's torque limit; unset: wingEffort()'s default for the pair count.
  std::optional<double> wing_effort;
  double wing_limit = 1.4;      // rad, hinge range +-limit
  double unit_spacing = 0.24;   // m between unit bodies along x
  double link_damping = 0.002;  // N m s/rad on the passive joints between units
  /// The axis of the passive joints between units. kRoll (the default): each unit rolls on
  /// its own and balances as the one-pair creature does, while the chain is rigid in pitch
  /// and yaw. kPitch (wave 1): the chain is rigid in roll and folds in pitch; with the
  /// one-pair controller on every unit, 20 tilted starts of 60 s at 1 ms fly 8/20 (4 units,
  /// springs 0.5 N m/rad), 1/20 (6) and 0/20 (12), against 18/20, 16/20 and 14/20 with roll
  /// joints (doc/flight_and_evolution.md).
  LinkAxis link_axis = LinkAxis::kRoll;
  /// N m/rad: a <spring> on each passive joint between units (0: none). 2 by default: it
  /// couples neighbouring units in roll, so that one unit's roll excursion does not twist
  /// the chain (a twisted chain's units beat at different mean rates and pitch it). With
  /// the chain pitch term (FlapControllerParams::pitch_gain), 20 tilted starts of 60 s at
  /// 1 ms (seed 7) fly 20/20 with the springs against 9/20 (6 units) and 8/20 (12 units)
  /// without, and 4/20 for a rigid 12-unit chain (fixed joints). 4 units fly 19/20 without.
  /// 2 stays below the explicit spring's cap (a quarter of the unit body's roll inertia per
  /// step squared, 2.9 N m/rad at 1 ms), so the chain is the same at every step size <= 1 ms.
  double link_stiffness = 2.0;
  double link_limit = 0.35;  // rad, passive joint range +-limit
  /// Feathering wings: each wing hangs from its hinge through a small root link and a pitch
  /// joint `unit<k>_wing_<side>_pitch` about its span (the wing's feather_joint).
  bool feathering = false;
  double root_mass = 0.001;  // kg, the small link between hinge and pitch joint
  double root_size = 0.01;   // m, its cube
  /// N m, pitch motor torque limit. 2: with the plate's added mass about its span (five
  /// times the wing's own pitch inertia) 0.5 N m overshot a 1.2 rad feather by 0.2 rad.
  double feather_effort = 2.0;
};

/// The hinge motors' default torque limit (N m). A plate's added mass in air (rho pi c^2 b /
/// 4, 16 g for the 0.22 x 0.35 m wing) is four times the wing's own: with it a lone unit at
/// 2 N m cannot reach its commanded rates and sinks under the evolved network (-12 to -22 m
/// in 30 s, 8 tilted starts), and at 8 N m it climbs (20/20 held-out starts fly at 1, 0.5
/// and 0.25 ms). Chained units keep 2 N m: their chain controllers fly 20/20 with it, and a
/// 4-unit chain at 8 N m flew none of 8 starts (doc/physics.md).
constexpr double kOnePairWingEffort = 8.0;
constexpr double kChainWingEffort = 2.0;

/// `params.wing_effort` if set, else kOnePairWingEffort for one pair and kChainWingEffort
/// for a chain.
double wingEffort(const FlapUnitParams& params, int pairs);

/// URDF text of a creature of `pairs` flap units (pairs >= 1) named
/// `<name>`. Unit k has body `unit<k>_body`, wings `unit<k>_wing_left/right`
/// on joints `unit<k>_wing_left/right_joint` (marked <wing>); units are
/// chained nose-to-tail by passive pitch joints `unit<k>_link_joint`.
/// Throws std::invalid_argument for pairs < 1.
std::string makeCreatureUrdf(int pairs, const std::string& name = "afc",
                             const FlapUnitParams& params = FlapUnitParams());

/// A hovering flier (make_creature --layout hover): a body hanging under two wings whose
/// stroke hinges turn about the body's vertical axis (a horizontal stroke plane, as
/// hummingbirds and flapping-wing robots hover) and whose membranes pitch about their spans
/// at mid-chord (feathering). Each wing: a spar `wing_<side>_spar` on the stroke hinge
/// `wing_<side>_joint` (marked <wing>, with a <motor>: the torque-speed line of stall_torque and
/// no_load_speed, at most max_power, and a parallel <spring> of hinge_stiffness if > 0), and
/// the membrane `wing_<side>` on the pitch joint `wing_<side>_pitch` (its feather_joint),
/// flown with the quasi-steady air model (<aero model="quasi_steady">); the spar feels no air.
struct HoverParams {
  double body_mass = 0.016;        // kg
  double body_length = 0.03;       // m, along x (forward)
  double body_width = 0.03;        // m, along y: the hinges sit on its sides
  double body_height = 0.07;       // m, along z
  double hinge_below_top = 0.02;   // m: the hinges lie this far below the body's top
  double com_drop = 0.0;           // m: the body's COM this far below the box centre
  double wing_span = 0.12;         // m, from the hinge to the tip
  double wing_chord = 0.045;       // m
  double wing_thickness = 0.0005;  // m
  double wing_mass = 0.0006;       // kg, the membrane
  double spar_mass = 0.0004;       // kg
  double spar_size = 0.003;        // m, its square section
  double stroke_limit = 1.5;       // rad, stroke hinge range +-limit
  double stall_torque = 0.06;      // N m, the stroke motor's
  double no_load_speed = 300.0;    // rad/s, the stroke motor's (0: a flat limit)
  double max_power = 3.0;          // W per stroke motor (0: none)
  double hinge_stiffness = 0.035;  // N m/rad, the parallel spring at each stroke hinge (0: none)
  double pitch_effort = 0.02;      // N m, the pitch motor's flat limit
};

/// URDF text of the hover creature named `name`. Throws std::invalid_argument for a size,
/// mass or torque that is not positive (a drop, speed, power or spring that is negative).
std::string makeHoverUrdf(const std::string& name = "hover",
                          const HoverParams& params = HoverParams());
/// The make_creature tool's settings.
struct MakeCreatureOptions {
  int pairs = 1;
  FlapUnitParams params;
  std::string layout = "chain";  // "chain" (makeCreatureUrdf) or "hover" (makeHoverUrdf)
  HoverParams hover;
  std::string name;    // empty: "afc" (chain) or "hover"
  std::string output;  // empty: stdout
};

/// The URDF `options` ask for (the chain or the hover layout).
std::string makeCreatureOutput(const MakeCreatureOptions& options);

/// The setter of a --link-axis flag (roll or pitch; InputError naming the flag otherwise).
std::function<void(const std::vector<std::string>&)> linkAxisSetter(LinkAxis* field);

/// make_creature's flags (flapsim/cli_args.h) over `options`.
CliParser makeCreatureCli(MakeCreatureOptions& options);

/// Empty if every flag `seen` (makeCreatureCli's parse) changes the creature `options` build;
/// else a message naming the first that would be ignored: the chain's flags with --layout
/// hover, the hover's without it, the joints between units' on a single unit.
std::string makeCreatureUnusedFlag(const MakeCreatureOptions& options,
                                   const std::vector<CliSeen>& seen);

}  // namespace flapsim
