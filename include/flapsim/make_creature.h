// Generator of flapping creatures: N flap units chained by passive joints.
#pragma once

#include <string>

namespace flapsim {

/// Dimensions and masses of one flapping unit (body + two wing plates).
struct FlapUnitParams {
  double body_length = 0.08;  // along x (forward)
  double body_width = 0.06;   // along y
  double body_height = 0.03;  // along z
  double body_mass = 0.015;
  /// The body's centre of mass lies this far below the wing hinges (a ballast under the
  /// body; the box stays where it is). Without it the unit is unstable in pitch: from a
  /// 0.1 rad pitch at 40/10/1.2 it drifts forward and pitches 30 deg within 6 s; with 2 cm
  /// it levels out (see README, creatures).
  double body_com_drop = 0.02;
  double wing_span = 0.35;   // along y, from the hinge to the tip
  double wing_chord = 0.22;  // along x
  double wing_thickness = 0.002;
  double wing_mass = 0.004;
  double wing_effort = 2.0;     // N m, hinge motor torque limit
  double wing_limit = 1.4;      // rad, hinge range +-limit
  double unit_spacing = 0.24;   // m between unit bodies along x
  double link_damping = 0.002;  // N m s/rad on the passive joints between units
  /// N m/rad: a <spring> on each passive joint between units (0: none). Without it the
  /// chains fold at these joints and flip; 0.5 lets the one-pair controller fly a 4-unit
  /// chain from 6 of 8 tilted starts (README, robust flight).
  double link_stiffness = 0.5;
  double link_limit = 0.35;  // rad, passive joint range +-limit
  /// Feathering wings: each wing hangs from its hinge through a small root link and a pitch
  /// joint `unit<k>_wing_<side>_pitch` about its span (the wing's feather_joint).
  bool feathering = false;
  double root_mass = 0.001;     // kg, the small link between hinge and pitch joint
  double root_size = 0.01;      // m, its cube
  double feather_effort = 0.5;  // N m, pitch motor torque limit
};

/// URDF text of a creature of `pairs` flap units (pairs >= 1) named
/// `<name>`. Unit k has body `unit<k>_body`, wings `unit<k>_wing_left/right`
/// on joints `unit<k>_wing_left/right_joint` (marked <wing>); units are
/// chained nose-to-tail by passive pitch joints `unit<k>_link_joint`.
/// Throws std::invalid_argument for pairs < 1.
std::string makeCreatureUrdf(int pairs, const std::string& name = "afc",
                             const FlapUnitParams& params = FlapUnitParams());

}  // namespace flapsim
